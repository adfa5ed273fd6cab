// dynid predict: a saved estimate applied to a dataset.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "reports/output.hpp"
#include "reports/prediction_report.hpp"

namespace dynid::cli {

int runPredict(const std::vector<std::string>& args) {
  po::options_description options("dynid predict");
  options.add_options()("estimate", po::value<std::string>()->required(),
                        "identify's estimate.json")("data", po::value<std::string>()->required(),
                                                    "dataset CSV")(
      "robot", po::value<std::string>(), "robot spec (default: the one the estimate names)")(
      "raw", po::value<std::string>(),
      "prepare --keep-raw-torque's validate_raw.csv for --data: also the error against the raw "
      "torque at the log's own stamps (the prediction interpolated there)")(
      "out", po::value<std::string>()->required(), "output directory");
  addThreadsOption(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid predict --estimate E --data D.csv --out DIR", vm))
    return kExitOk;
  const std::string dir = vm["out"].as<std::string>();
  checkOutputDirectory(dir);  // before the work, not after it
  PredictRequest request{vm["estimate"].as<std::string>(), vm["data"].as<std::string>(),
                         vm.count("robot") ? vm["robot"].as<std::string>() : ""};
  request.threads = threadsOption(vm);
  if (vm.count("raw")) request.raw_file = vm["raw"].as<std::string>();
  PredictedCsv csv(dir);  // every sample's prediction, written as the data stream through
  request.sink = &csv;
  const PredictOutcome outcome = predictRun(request);
  std::cout << writePrediction(dir, outcome, request.estimate_file, request.data_file, csv);
  return kExitOk;
}

}  // namespace dynid::cli
