// dynid identifiability: which standard parameters (and combinations) the torques determine.
#include <filesystem>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/identification_output.hpp"
#include "core/parameters.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"

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
  po::variables_map vm;
  const std::string usage =
      "dynid identifiability --robot R [--drives] [--data F.csv] [--samples N] [--seed S] --out "
      "DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const Model model = loadRobotFromOptions(vm);
  const BaseParameters base = structuralBaseParameters(model, vm);
  nlohmann::json report = identifiabilityJson(model, base, vm);
  std::string data_summary;
  if (vm.count("data")) {
    const std::string file = vm["data"].as<std::string>();
    const Observation observation =
        observationFromTrajectory(model, readDatasetCsv(file, model.numJoints()));
    report["data"] = excitationJson(base, observation, file);
    data_summary = "; the data reach rank " + std::to_string(report["data"]["rank"].get<int>());
  }
  const std::string dir = vm["out"].as<std::string>();
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir + "/identifiability.json", report.dump(2) + "\n");
  writeFileAtomically(dir + "/identifiability.md", identifiabilityMarkdown(report));
  if (base.rankGap() < 1e3)
    std::cerr << "warning: the rank gap is only " << formatShort(base.rankGap())
              << ": the structural rank is ambiguous; try more --samples or another --tolerance\n";
  std::cout << model.name << ": " << base.numStandard() << " standard parameters, "
            << base.numBase() << " base parameters (rank gap " << formatShort(base.rankGap())
            << "), " << base.zero_columns.size() << " never affect the torques" << data_summary
            << "\nwrote " << dir << "/identifiability.json and " << dir << "/identifiability.md\n";
  return kExitOk;
}

}  // namespace dynid::cli
