// dynid predict: a saved estimate, or any robot model, applied to a dataset.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "reports/output.hpp"
#include "reports/prediction_report.hpp"

namespace dynid::cli {

int runPredict(const std::vector<std::string>& args) {
  po::options_description options("dynid predict");
  options.add_options()("estimate", po::value<std::string>(),
                        "identify's estimate.json (its robot, drive terms and parameters)")(
      "data", po::value<std::string>()->required(), "dataset CSV")(
      "raw", po::value<std::string>(),
      "prepare --keep-raw-torque's validate_raw.csv for --data: also the error against the raw "
      "torque at the log's own stamps (the prediction interpolated there)")(
      "out", po::value<std::string>()->required(), "output directory");
  // --robot alone: that model's own parameters (a URDF, identify --write-urdf's copy, a .json
  // model, a built-in); with --estimate: the robot the estimate is applied to.
  addRobotOptions(options, false);
  addRestVelocityOption(options);
  addTorqueFilterOption(options,
                        "the low-pass --data's torque went through, which the comparison "
                        "reproduces on the model's friction that needs sign(dq), as identify's "
                        "held-out error does");
  addThreadsOption(options);
  po::variables_map vm;
  const std::string usage =
      "dynid predict (--estimate estimate.json [--robot R] | --robot R [--drives]) --data D.csv "
      "--out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const bool estimate = vm.count("estimate") > 0;
  if (!estimate && !vm.count("robot"))
    throw UsageError(
        "give --estimate estimate.json, or --robot R to predict with a model's own "
        "parameters");
  refuseUnused(vm, !estimate, {"drives", "drive-terms", "strict"},
               "applies to --robot alone (an estimate carries its own drive terms)");
  const std::string dir = outputDirectoryOption(vm);
  PredictRequest request;
  request.estimate_file = estimate ? vm["estimate"].as<std::string>() : "";
  request.data_file = vm["data"].as<std::string>();
  request.robot_spec = vm.count("robot") ? vm["robot"].as<std::string>() : "";
  if (!estimate) request.model = loadRobotFromOptions(vm);
  request.threads = threadsOption(vm);
  if (vm.count("raw")) request.raw_file = vm["raw"].as<std::string>();
  request.rest_velocity = restVelocityOption(vm, request.model ? request.model->numJoints() : 0);
  request.torque_filter = torqueFilterOption(vm);
  PredictedCsv csv(dir);  // every sample's prediction, written as the data stream through
  request.sink = &csv;
  const PredictOutcome outcome = predictRun(request);
  printWarnings(outcome.warnings);
  std::cout << writePrediction(dir, outcome, request.estimate_file, request.data_file, csv);
  return kExitOk;
}

}  // namespace dynid::cli
