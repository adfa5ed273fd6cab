// dynid identify: least-squares estimate of the base parameters from a torque dataset.
#include <filesystem>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/identification_output.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"

namespace dynid::cli {

int runIdentify(const std::vector<std::string>& args) {
  po::options_description options("dynid identify");
  addRobotOptions(options);
  addStructuralOptions(options);
  options.add_options()("method", po::value<std::string>()->default_value("ols"),
                        "ols (ordinary) or wls (weighted per joint, Gautier)")(
      "data", po::value<std::string>()->required(), "training dataset CSV")(
      "validate", po::value<std::string>(), "held-out dataset CSV: torque RMS per joint")(
      "out", po::value<std::string>()->required(), "output directory (estimate.json, estimate.md)");
  po::variables_map vm;
  const std::string usage =
      "dynid identify --method ols|wls --robot R [--drives] --data train.csv [--validate test.csv] "
      "--out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  LeastSquaresMethod method;
  try {
    method = parseLeastSquaresMethod(vm["method"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(std::string("--method: ") + e.what());
  }
  const Model model = loadRobotFromOptions(vm);
  const std::string data_file = vm["data"].as<std::string>();
  const Observation train =
      observationFromTrajectory(model, readDatasetCsv(data_file, model.numJoints()));
  const BaseParameters base = structuralBaseParameters(model, vm);
  const BaseEstimate estimate = estimateBaseParameters(base, train, method);
  nlohmann::json report = estimateJson(model, base, estimate, data_file);
  if (vm.count("validate")) {
    const std::string file = vm["validate"].as<std::string>();
    const Observation test =
        observationFromTrajectory(model, readDatasetCsv(file, model.numJoints()));
    report["validation"] = validationJson(validateBaseEstimate(base, estimate.beta, test), file);
  }
  const std::string dir = vm["out"].as<std::string>();
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir + "/estimate.json", report.dump(2) + "\n");
  writeFileAtomically(dir + "/estimate.md", estimateMarkdown(report));
  std::cout << model.name << ": " << leastSquaresMethodName(method) << " estimate of "
            << base.numBase() << " base parameters from " << train.num_samples
            << " samples, condition number " << formatShort(estimate.condition_number)
            << ", residual RMS "
            << formatShort(estimate.residual_rms.norm() / std::sqrt(model.numJoints())) << " N m";
  if (vm.count("validate"))
    std::cout << ", held-out RMS "
              << formatShort(report["validation"]["torque_rms"].get<std::vector<double>>().front());
  std::cout << "\nwrote " << dir << "/estimate.json and " << dir << "/estimate.md\n";
  return kExitOk;
}

}  // namespace dynid::cli
