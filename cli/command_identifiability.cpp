// dynid identifiability: which standard parameters (and combinations) the torques determine.
#include <iostream>

#include "analysis/records/provenance.hpp"
#include "cli/command_floating.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/identification_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

int runIdentifiability(const std::vector<std::string>& args) {
  po::options_description options("dynid identifiability");
  addRobotOptions(options);
  addStructuralOptions(options);
  options.add_options()("data", po::value<std::string>(),
                        "dataset CSV: also report the rank it achieves and how well it excites "
                        "each base parameter")(
      "out", po::value<std::string>()->required(),
      "output directory (identifiability.json, identifiability.md)");
  addFloatingOptions(
      options, "reports what each sensor set determines (floating_identifiability.json, .md)");
  addThreadsOption(options);
  po::variables_map vm;
  const std::string usage =
      "dynid identifiability --robot R [--drives] [--data F.csv] [--samples N] [--seed S] --out "
      "DIR\n       dynid identifiability --robot R.urdf --floating-base [--contacts L1,L2:frame] "
      "[--sensors S1,S2] [--motion holding|free|suspended|carried] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  if (vm["floating-base"].as<bool>()) return runFloatingIdentifiability(vm);
  refuseFloatingOptions(vm, {"contacts", "sensors", "motion"});
  const StructuralOptions structural = structuralOptions(vm);
  const Model model = loadRobotFromOptions(vm);
  const IdentifiabilityOutcome outcome = identifiabilityRun(
      model, structural, vm.count("data") ? vm["data"].as<std::string>() : "", threadsOption(vm));
  const nlohmann::json report = identifiabilityJson(model, outcome);
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(dir, {{"identifiability.json", jsonText(withProvenance(report), 2) + "\n"},
                         {"identifiability.md", identifiabilityMarkdown(model, outcome)}});
  if (outcome.base.rankGap() < 1e4)
    std::cerr << "warning: the rank gap is only " << formatNumber(outcome.base.rankGap(), 4)
              << " (below 1e4): the structural rank is a close call; try more --samples or another "
                 "--tolerance\n";
  std::cout << identifiabilitySummary(model, outcome, dir);
  return kExitOk;
}

}  // namespace dynid::cli
