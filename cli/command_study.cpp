// dynid study: every method on the user's own log, torque fit and motion prediction side by side
// (analysis/studies/log_study.hpp), with its report.
#include <iostream>
#include <optional>
#include <string>

#include "analysis/studies/log_study.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/format.hpp"
#include "reports/identification_report.hpp"
#include "reports/log_study_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// The report's next step as the dynid identify command that repeats it.
std::string identifyCommand(const StudyRepeat& r) {
  std::string command = "dynid identify --method " + r.method + " --robot " +
                        shellWord(r.robot_spec) + " --drive-terms " + shellWord(r.drive_terms) +
                        " --data " + shellWord(r.data_file) + " --validate " +
                        shellWord(r.validate_file) + " --out " + shellWord(r.out);
  const auto number = [&](const char* flag, const std::optional<double>& x) {
    if (x) command += std::string(" ") + flag + " " + formatNumber(*x);
  };
  number("--prior-weight", r.prior_weight);
  number("--combined-weight", r.combined_weight);
  number("--combined-seconds", r.combined_seconds);
  if (r.combined_iterations)
    command += " --combined-iterations " + std::to_string(*r.combined_iterations);
  number("--horizon", r.horizon);
  if (r.segments) command += " --segments " + std::to_string(*r.segments);
  if (r.raw_gc) command += " --raw-gc";
  if (r.front && r.front_weights.empty()) command += " --front";
  if (!r.front_weights.empty()) {
    command += " --front-weights ";
    for (std::size_t k = 0; k < r.front_weights.size(); ++k) {
      if (k > 0) command += ",";
      command += formatNumber(r.front_weights[k]);
    }
  }
  number("--front-tolerance", r.front_tolerance);
  if (!r.write_urdf.empty()) command += " --write-urdf " + shellWord(r.write_urdf);
  return command;
}

/// study's options, in the order --help lists them (every default the request's own).
void addStudyOptions(po::options_description& options) {
  addRobotOptions(options);
  const LogStudyRequest d;  // every default is the request's own
  options.add_options()("data", po::value<std::string>()->required(), "training dataset CSV")(
      "validate", po::value<std::string>()->required(), "held-out dataset CSV")(
      "methods", po::value<std::string>()->default_value("all"),
      "comma-separated methods, or all (ols,wls,pc,nlo,ga,hybrid and the *_refined)")(
      "horizon", po::value<double>()->default_value(d.segments.horizon))(
      "segments", po::value<int>()->default_value(d.segments.num_segments))(
      "search-seconds", po::value<double>()->default_value(d.search_seconds))(
      "search-evaluations", po::value<long>()->default_value(d.search_evaluations))(
      "refine-iterations", po::value<int>()->default_value(d.refine_iterations))(
      "refine-seconds", po::value<double>()->default_value(d.refine_seconds),
      "per refinement, and the combined estimator's")(
      "combined-weight", po::value<double>()->default_value(d.combined_weight))(
      "raw-gc", po::bool_switch(),
      "GC errors in rad and rad/s (default: each joint's q and dq errors divided by their "
      "spread over the data, so no joint's velocity dominates the ranking)")(
      "seed", po::value<std::uint64_t>()->default_value(d.seed), "seed of the searches")(
      "write-urdf", po::value<std::string>(),
      "with --front, for a URDF robot: a copy of it carrying the chosen estimate, and the full "
      "model as .dynid.json beside it")("out", po::value<std::string>()->required(),
                                        "output directory");
  addFrontOptions(options,
                  "also sweep the combined estimator's GC weight (0.01 to 100, each point from "
                  "the last) and choose one estimate from every consistent one by "
                  "--front-tolerance (written as chosen.json)");
  addPriorWeightOption(options);
  addKeepRefinementOption(options);
  addThreadsOption(options);
}

}  // namespace

int runStudy(const std::vector<std::string>& args) {
  po::options_description options("dynid study");
  addStudyOptions(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid study --robot R [--drive-terms T] --data train.csv --validate "
                        "held.csv --out DIR",
                        vm))
    return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  LogStudyRequest request;
  request.robot = loadRobotFromOptions(vm);
  request.robot_spec = vm["robot"].as<std::string>();
  request.data_file = vm["data"].as<std::string>();
  request.validate_file = vm["validate"].as<std::string>();
  request.methods =
      parseOption(vm, "methods", [](const std::string& list) { return parseMethods(list); });
  request.segments.horizon = vm["horizon"].as<double>();
  request.segments.num_segments = vm["segments"].as<int>();
  request.segments.seed = vm["seed"].as<std::uint64_t>();
  request.segments.normalise = !vm["raw-gc"].as<bool>();
  request.combined_weight = vm["combined-weight"].as<double>();
  request.front_weights = frontWeightsOption(vm);
  request.front_tolerance = vm["front-tolerance"].as<double>();
  if (vm.count("write-urdf")) {
    if (request.front_weights.empty())
      throw UsageError("--write-urdf writes the estimate chosen from the front: add --front");
    request.write_back_from = writeUrdfSource(vm, request.robot_spec);
  }
  request.search_seconds = vm["search-seconds"].as<double>();
  request.search_evaluations = vm["search-evaluations"].as<long>();
  if (request.search_seconds == 0.0 && request.search_evaluations == 0)
    throw UsageError("a search needs a budget: --search-seconds or --search-evaluations > 0");
  request.refine_iterations = vm["refine-iterations"].as<int>();
  request.refine_seconds = vm["refine-seconds"].as<double>();
  request.seed = vm["seed"].as<std::uint64_t>();
  request.prior_weight = priorWeightOption(vm);
  request.keep_if_better = keepIfBetterOption(vm);
  request.threads = threadsOption(vm);
  if (stderrIsTerminal())
    request.control.progress = [](const std::string& line) {
      std::cerr << "[study] " << line << "\n";
    };
  const InterruptGuard guard;
  request.control.stop = guard.flag();
  const LogStudyOutcome outcome = logStudyRun(request);
  std::cout << writeLogStudy(vm["out"].as<std::string>(), outcome, identifyCommand);
  if (outcome.write_back)
    std::cout << writeWriteBack(vm["write-urdf"].as<std::string>(), *outcome.write_back);
  else if (vm.count("write-urdf"))
    std::cerr << "warning: --write-urdf: no estimate was chosen ("
              << (outcome.interrupted ? "interrupted before the front" : "none qualifies")
              << "), so nothing was written\n";
  return exitAfter(guard, "study",
                   "the report has the methods that finished and each stopped one's best so far");
}

}  // namespace dynid::cli
