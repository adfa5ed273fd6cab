// dynid identifiability: which standard parameters (and combinations) the torques determine.
#include <iostream>

#include "analysis/records/provenance.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "data/robots.hpp"
#include "reports/floating_report.hpp"
#include "reports/identification_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {
/// The floating-base analysis: what each sensor set determines.
int runFloatingIdentifiability(const po::variables_map& vm) {
  if (vm.count("data"))
    throw UsageError(
        "--data with --floating-base: a floating-base dataset's excitation is not "
        "measured yet; the analysis is structural (docs/FLOATING.md)");
  FloatingIdentifiabilityRequest request;
  request.structural = structuralOptions(vm);
  request.contacts = nameListOption(vm, "contacts");
  try {
    for (const std::string& name : nameListOption(vm, "sensors"))
      request.sensors.push_back(parseSensorSet(name));
    if (vm.count("motion")) request.motion = parseFloatingMotion(vm["motion"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  const RobotOptions robot = robotOptions(vm);
  std::vector<std::string> warnings;
  const FloatingModel model = loadFloatingRobot(vm["robot"].as<std::string>(), robot, &warnings);
  printWarnings(warnings);
  const FloatingIdentifiabilityOutcome outcome = floatingIdentifiabilityRun(model, request);
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(
      dir, {{"floating_identifiability.json",
             jsonText(withProvenance(floatingIdentifiabilityJson(model, outcome)), 2) + "\n"},
            {"floating_identifiability.md", floatingIdentifiabilityMarkdown(model, outcome)}});
  for (const SensorSetBase& s : outcome.sets)
    if (s.base.rankGap() < 1e4)
      std::cerr << "warning: " << sensorSetName(s.set) << ": the rank gap is only "
                << formatNumber(s.base.rankGap(), 4)
                << " (below 1e4): a close call; try more --samples\n";
  std::cout << floatingIdentifiabilitySummary(model, outcome, dir);
  return kExitOk;
}
}  // namespace

int runIdentifiability(const std::vector<std::string>& args) {
  po::options_description options("dynid identifiability");
  addRobotOptions(options);
  addStructuralOptions(options);
  options.add_options()("data", po::value<std::string>(),
                        "dataset CSV: also report the rank it achieves and how well it excites "
                        "each base parameter")(
      "out", po::value<std::string>()->required(),
      "output directory (identifiability.json, identifiability.md)")(
      "floating-base", po::bool_switch(),
      "the robot (a URDF) floats: a free-flyer joint at its root; reports what each sensor set "
      "determines (floating_identifiability.json, .md)")(
      "contacts", po::value<std::string>(),
      "with --floating-base: the links that touch the world, comma-separated, each NAME (a point "
      "force), NAME:point or NAME:frame (a wrench, a flat foot)")(
      "sensors", po::value<std::string>(),
      "with --floating-base: wrenches, torques_wrenches, torques_contacts (comma-separated; "
      "default all)")(
      "motion", po::value<std::string>(),
      "with --floating-base: holding (contacts hold; the default with --contacts), free (nothing "
      "holds; the default without) or suspended (the base held still)");
  addThreadsOption(options);
  po::variables_map vm;
  const std::string usage =
      "dynid identifiability --robot R [--drives] [--data F.csv] [--samples N] [--seed S] --out "
      "DIR\n       dynid identifiability --robot R.urdf --floating-base [--contacts L1,L2:frame] "
      "[--sensors S1,S2] [--motion holding|free|suspended] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  if (vm["floating-base"].as<bool>()) return runFloatingIdentifiability(vm);
  for (const char* floating_only : {"contacts", "sensors", "motion"})
    if (vm.count(floating_only))
      throw UsageError(std::string("--") + floating_only + " needs --floating-base");
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
