// dynid identify: least-squares estimate of the base parameters from a torque dataset.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "analysis/runs/summarize.hpp"
#include "cli/command_floating.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "reports/identification_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// The combined estimator's options (their defaults are the request's own).
void addCombinedOptions(po::options_description& options) {
  const IdentifyRequest d;
  options.add_options()("horizon", po::value<double>()->default_value(d.segments.horizon),
                        "combined, and with --floating-base (each estimate's GC error): GC "
                        "error horizon [s]")(
      "segments", po::value<int>()->default_value(d.segments.num_segments),
      "combined, and with --floating-base: GC error segments (at most that fit)")(
      "raw-gc", po::bool_switch(),
      "combined: GC residuals in rad and rad/s (default: each joint's q and dq errors divided by "
      "their spread over the data)")("combined-weight",
                                     po::value<double>()->default_value(d.combined.gc_weight))(
      "no-gc-floor", po::bool_switch(),
      "combined: fit the GC error below its noise floor too (what the torque noise alone causes; "
      "the default holds the GC term there, since fitting noise biases the parameters)")(
      "combined-seconds", po::value<double>()->default_value(d.combined.max_seconds))(
      "combined-iterations", po::value<int>()->default_value(d.combined.max_iterations));
  addFrontOptions(options,
                  "combined: sweep the GC weight (0.01 to 100, each point from the last, "
                  "--combined-weight unused) and take the estimate the held-out data (--validate) "
                  "choose by --front-tolerance, as dynid study --front does");
}

/// Refuses them with another method (usage error), else reads them into the request.
void readCombinedOptions(const po::variables_map& vm, IdentifyRequest& request) {
  refuseUnused(
      vm, request.method == Method::kCombined,
      {"horizon", "segments", "raw-gc", "combined-weight", "no-gc-floor", "combined-seconds",
       "combined-iterations", "front", "front-weights", "front-tolerance"},
      "applies to --method combined");
  request.front_weights = frontWeightsOption(vm);
  if (!request.front_weights.empty() && !vm.count("validate"))
    throw UsageError("--front chooses its estimate on held-out data: give --validate");
  refuseUnused(vm, !request.front_weights.empty(), {"front-tolerance"}, "applies with --front");
  refuseUnused(vm, request.front_weights.empty(), {"combined-weight"},
               "is what --front sweeps (its weights: --front-weights)");
  request.front_tolerance = vm["front-tolerance"].as<double>();
  request.segments.horizon = vm["horizon"].as<double>();
  request.segments.num_segments = vm["segments"].as<int>();
  request.segments.normalise = !vm["raw-gc"].as<bool>();
  request.combined.gc_weight = vm["combined-weight"].as<double>();
  request.combined.noise_floor = !vm["no-gc-floor"].as<bool>();
  request.combined.max_seconds = vm["combined-seconds"].as<double>();
  request.combined.max_iterations = vm["combined-iterations"].as<int>();
}

/// identify's options, in the order --help lists them.
void addIdentifyOptions(po::options_description& options) {
  addRobotOptions(options, false);
  addStructuralOptions(options);
  options.add_options()(
      "method", po::value<std::string>()->default_value("ols"),
      "ols (ordinary), wls (weighted per joint, Gautier), pc (physically consistent: least "
      "squares regularised by the entropic divergence from the prior) or combined (pc's fit of "
      "the torques and the motion's GC residuals together, physically consistent); with "
      "--floating-base ols, wls (each channel's noise estimated; the default there), pc or "
      "combined")("prior", po::value<std::string>(),
                  "pc, combined: prior model (robot spec; default: the robot's own parameters)")(
      "data", po::value<std::string>(), "training dataset CSV")(
      "summaries", po::value<std::vector<std::string>>()->multitoken(),
      "or least-squares summaries of the training logs (dynid summarize), merged: the same ols, "
      "wls or pc estimate as the logs give (the robot: theirs, or --robot's if it matches)")(
      "validate", po::value<std::string>(), "held-out dataset CSV: torque RMS per joint")(
      "validate-raw", po::value<std::string>(),
      "prepare --keep-raw-torque's validate_raw.csv for --validate: also the error against the "
      "raw torque at the log's own stamps")(
      "out", po::value<std::string>()->required(),
      "output directory (estimate.json, report.md, report.html)")(
      "write-urdf", po::value<std::string>(),
      "for a URDF robot: a copy of it carrying the estimate (pc, or a consistent ols/wls), and "
      "the full model as .dynid.json beside it")(
      "covariance", po::value<std::string>()->default_value("hac"),
      "the estimate's covariance: hac (robust to heteroscedastic and correlated residuals, over "
      "batches of consecutive samples whose length "
      "follows the residuals' correlation, so that filtered logs and model error widen it; a "
      "second pass over the data) or white (sigma^2 (W^T W)^-1, residuals taken as white; one "
      "pass)");
  addTorqueFilterOption(options,
                        "the low-pass the training torque went through, whose effect on the "
                        "friction columns that need sign(dq) the fit reproduces (parallel "
                        "filtering)");
  addCombinedOptions(options);
  addFloatingOptions(options,
                     "estimates each sensor set the floating dataset --data feeds "
                     "(floating_identification.json, .md)");
  options.add_options()("payload-link", po::value<std::string>(),
                        "with --floating-base: also the payload fixed to this link (a box on the "
                        "base, a tool on an arm): its ten parameters from each set, the robot "
                        "read as unloaded")(
      "unloaded", po::value<std::string>(),
      "with --payload-link: a floating dataset of the robot without the payload; the payload "
      "then comes from the two datasets' estimates, not from the robot's parameters");
  addPriorWeightOption(options);
  addRestVelocityOption(options);
  addThreadsOption(options);
}

/// The training data: --data (with --robot), or --summaries read and merged into `merged` (the
/// robot theirs unless --robot names one; identifyRun checks that it matches).
void readTrainingSource(const po::variables_map& vm, IdentifyRequest& request,
                        std::optional<Summary>& merged) {
  const bool summaries = vm.count("summaries") > 0;
  if (summaries == (vm.count("data") > 0))
    throw UsageError("give the training data as --data or as --summaries, one of them");
  refuseUnused(vm, !summaries, {"torque-filter", "rest-velocity"},
               "applies with --data (a summary holds each log's own)");
  if (!summaries) {
    if (!vm.count("robot")) throw UsageError("--data needs --robot");
    request.model = loadRobotFromOptions(vm);
    request.robot_spec = vm["robot"].as<std::string>();
    request.data_file = vm["data"].as<std::string>();
    request.rest_velocity = restVelocityOption(vm, request.model.numJoints());
    request.torque_filter = torqueFilterOption(vm);
    return;
  }
  if (request.method == Method::kCombined)
    throw UsageError(
        "--method combined rolls the model out over the samples, which a summary "
        "does not hold: give --data");
  const std::vector<std::string> files = vm["summaries"].as<std::vector<std::string>>();
  std::vector<Summary> read;
  for (const std::string& file : files) read.push_back(readSummary(file));
  std::vector<const Summary*> all;
  for (const Summary& s : read) all.push_back(&s);
  merged = mergeSummaries(all, files);
  request.summary = &*merged;
  request.summary_name =
      files.size() == 1 ? files.front()
                        : std::to_string(files.size()) + " summaries (" + files.front() + ", ...)";
  if (vm.count("robot")) {
    request.model = loadRobotFromOptions(vm);
    request.robot_spec = vm["robot"].as<std::string>();
  } else {
    request.model = merged->model;
    request.robot_spec = merged->model_source.spec;
  }
}

}  // namespace

int runIdentify(const std::vector<std::string>& args) {
  po::options_description options("dynid identify");
  addIdentifyOptions(options);
  po::variables_map vm;
  const std::string usage =
      "dynid identify --method ols|wls|pc|combined --robot R [--drives] --data train.csv "
      "[--validate test.csv] --out DIR\n       dynid identify --method ols|wls|pc --summaries "
      "S.summary.json... [--validate test.csv] --out DIR\n       dynid identify --robot R.urdf "
      "--floating-base --data F.csv [--contacts L1,L2:frame] [--sensors S1,S2] [--method "
      "ols|wls|pc|combined] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  if (vm["floating-base"].as<bool>()) return runFloatingIdentify(vm);
  refuseFloatingOptions(vm, {"contacts", "sensors", "motion", "payload-link", "unloaded"});
  IdentifyRequest request;
  request.method = parseOption(
      vm, "method", [](const std::string& name) { return parseMethod(name, identifyMethods()); });
  const bool physical = takesPrior(request.method);
  refuseUnused(
      vm, physical, {"prior", "prior-weight"},
      "applies to --method pc or combined, not " + std::string(methodName(request.method)));
  readCombinedOptions(vm, request);
  request.prior_weight = priorWeightOption(vm);
  request.structural = structuralOptions(vm);
  std::optional<Summary> merged;
  readTrainingSource(vm, request, merged);
  if (physical && vm.count("prior")) request.prior = loadOtherRobot(vm, "prior");
  request.threads = threadsOption(vm);
  request.covariance = parseOption(vm, "covariance", covariancePolicyFrom);
  if (vm.count("validate")) request.validate_file = vm["validate"].as<std::string>();
  refuseUnused(vm, vm.count("validate") > 0, {"validate-raw"}, "applies with --validate");
  if (vm.count("validate-raw")) request.validate_raw_file = vm["validate-raw"].as<std::string>();
  if (vm.count("write-urdf")) request.write_back_from = writeUrdfSource(vm, request.robot_spec);
  if (stderrIsTerminal())
    request.combined.control.progress = [](const std::string& line) {
      std::cerr << "[identify] " << line << "\n";
    };
  // combined stops at its next rollout on Ctrl-C, keeping its best so far; the other methods
  // keep the default (the process ends, leaving no partial output).
  std::optional<InterruptGuard> guard;
  if (request.method == Method::kCombined) request.combined.control.stop = guard.emplace().flag();
  const IdentifyOutcome outcome = identifyRun(request);
  if (outcome.write_back)
    std::cout << writeWriteBack(vm["write-urdf"].as<std::string>(), *outcome.write_back);
  if (const std::string warning = solverWarning(outcome); !warning.empty())
    std::cerr << "warning: " << warning << "\n";
  // The summary names request fields (`torque_filter`) as this command's flags.
  std::cout << cliText(writeIdentification(vm["out"].as<std::string>(), request.model, outcome));
  if (guard) return exitAfter(*guard, "identify", "the combined estimate is its best so far");
  return kExitOk;
}

}  // namespace dynid::cli
