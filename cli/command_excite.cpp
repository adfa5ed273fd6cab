// dynid excite: design the motion that makes every base parameter visible
// (analysis/excitation/excite.hpp).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include "analysis/excitation/excite.hpp"
#include "analysis/floating/stand_tilts.hpp"
#include "cli/command_floating.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "data/robots.hpp"
#include "reports/excitation_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {
void addExciteOptions(po::options_description& options) {
  const ExciteRequest d;  // every default is the request's own
  const LimitOverrides limits;
  options.add_options()(
      "payload", po::bool_switch(),
      "a payload motion (<= 20 s, default 15 s): determine the last link's 10 parameters, the arm "
      "known (dynid payload)")("payload-link", po::value<std::string>(),
                               "--payload for this link instead of the last")(
      "payload-proximal-share",
      po::value<double>()->default_value(ExciteRequest{}.payload_proximal_share))(
      "criterion", po::value<std::string>()->default_value("cond"),
      "what to minimise: cond (unit-column condition number of the base regressor), "
      "cond-unscaled (in SI units), d-optimal (-log det of the information per row), gc (the "
      "first-order GC error sensitivity M^-1 W1) or relative-sd (the RMS expected standard "
      "deviation of the base parameters relative to the model's values)")(
      "period", po::value<double>()->default_value(d.period))(
      "harmonics", po::value<int>()->default_value(d.harmonics))(
      "offset", po::value<std::string>(),
      "fixed centre of each joint's motion [rad] (default: optimised from the middle of the "
      "limits)")("q-min", po::value<std::string>(),
                 "lower position limits [rad] (default: the "
                 "model's)")("q-max", po::value<std::string>(),
                             "upper position limits [rad] (default: the model's)")(
      "dq-max", po::value<std::string>(), "velocity limits [rad/s] (default: the model's, else 2)")(
      "ddq-max", po::value<std::string>(),
      "acceleration limits [rad/s^2] (default: the model's, else 5)")(
      "tau-max", po::value<std::string>(),
      "torque limits [N m] (default: the model's effort limits, else none)")(
      "torque-margin", po::value<double>()->default_value(limits.torque_margin))(
      "floor", po::value<double>())("base-radius",
                                    po::value<double>()->default_value(limits.base_radius))(
      "starts", po::value<int>()->default_value(d.starts))(
      "evaluations", po::value<int>()->default_value(d.evaluations))(
      "budget-seconds", po::value<double>()->default_value(0.0))(
      "grid-rate", po::value<double>()->default_value(d.grid_rate))(
      "check-rate", po::value<double>()->default_value(d.check_rate))(
      "csv-rate", po::value<double>()->default_value(ExcitationSettings{}.csv_rate))(
      "segments", po::value<int>()->default_value(d.gc_segments))(
      "horizon", po::value<double>()->default_value(d.gc_horizon))(
      "torque-noise", po::value<double>()->default_value(d.torque_noise))(
      "stands", po::value<int>(),
      "for the robot on a stand with a force-torque sensor under its base: also choose this many "
      "stand orientations (upright first) to run the design at, for its support's six rows "
      "(docs/FLOATING.md)")("max-tilt",
                            po::value<double>()->default_value(StandTiltRequest{}.max_tilt),
                            "--stands: the largest roll and pitch [rad]")(
      "tilt-grid", po::value<int>()->default_value(StandTiltRequest{}.tilt_grid),
      "--stands: candidates per axis (odd)")(
      "out", po::value<std::string>()->required(),
      "output directory (excitation.json, excitation.csv, report.md, report.html)");
  addThreadsOption(options);
  addFloatingExciteOptions(options);
}

/// --payload and --payload-link: a payload motion for that link (15 s, d-optimal by default).
void applyPayloadOptions(const po::variables_map& vm, ExciteRequest& request) {
  const int n = request.robot.numJoints();
  refuseUnused(vm, vm["payload"].as<bool>() || vm.count("payload-link") > 0,
               {"payload-proximal-share"}, "applies to --payload");
  if (vm["payload"].as<bool>() || vm.count("payload-link")) {
    request.payload_link = n - 1;
    if (vm.count("payload-link")) {
      const std::string link = vm["payload-link"].as<std::string>();
      const auto at =
          std::find(request.robot.link_names.begin(), request.robot.link_names.end(), link);
      if (at == request.robot.link_names.end())
        throw UsageError("--payload-link: '" + link + "' is not a moving link of the robot");
      request.payload_link = static_cast<int>(at - request.robot.link_names.begin());
    }
    if (!given(vm, "period")) request.period = 15.0;
    request.payload_proximal_share = vm["payload-proximal-share"].as<double>();
    if (request.period > 20.0)
      throw UsageError("--period: a payload motion lasts at most 20 s (--payload)");
    // The payload's information (D-optimality): the condition number alone buys a round
    // information matrix with less of it (docs/PAYLOAD.md, "A payload motion").
    if (!given(vm, "criterion")) request.criterion = ExcitationCriterion::kDOptimal;
  }
}

/// The limits (the robot's, overridden by the options) and the offsets checked against them.
void applyLimitOptions(const po::variables_map& vm, ExciteRequest& request) {
  const int n = request.robot.numJoints();
  LimitOverrides overrides;
  overrides.q_min = optionalJointVector(vm, "q-min", n, true);
  overrides.q_max = optionalJointVector(vm, "q-max", n, true);
  overrides.dq_max = optionalJointVector(vm, "dq-max", n, true);
  overrides.ddq_max = optionalJointVector(vm, "ddq-max", n, true);
  overrides.tau_max = optionalJointVector(vm, "tau-max", n, true);
  overrides.torque_margin = vm["torque-margin"].as<double>();
  if (vm.count("floor")) overrides.floor = vm["floor"].as<double>();
  overrides.base_radius = vm["base-radius"].as<double>();
  try {
    request.limits = excitationLimits(request.robot, overrides);
  } catch (const InputError& e) {
    throw UsageError(std::string("the limits: ") + e.what());
  }
  if (request.offset) try {
      checkOffsets(request.robot, request.limits, *request.offset);
    } catch (const InputError& e) {
      throw UsageError(std::string("--offset: ") + e.what());
    }
}
/// --stands, --max-tilt and --tilt-grid: the stand request (its design set after the run) and the
/// robot with a floating base, both checked before the work.
struct StandOptions {
  StandTiltRequest request;
  FloatingModel model;
};

std::optional<StandOptions> standOptions(const po::variables_map& vm,
                                         const ExciteRequest& request) {
  refuseUnused(vm, vm.count("stands") > 0, {"max-tilt", "tilt-grid"}, "applies to --stands");
  if (!vm.count("stands")) return std::nullopt;
  if (request.payload_link)
    throw UsageError(
        "--stands: a payload motion is for one link of an arm, not a robot on a stand");
  StandTiltRequest stand;
  stand.stands = vm["stands"].as<int>();
  stand.max_tilt = vm["max-tilt"].as<double>();
  stand.tilt_grid = vm["tilt-grid"].as<int>();
  stand.structural = request.structural;
  stand.design.period = request.period;  // the check's placeholder until the design is made
  try {
    stand.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  std::vector<std::string> warnings;  // said when the robot was loaded for the design
  FloatingModel model =
      loadFloatingRobot(vm["robot"].as<std::string>(), robotOptions(vm), &warnings);
  return StandOptions{stand, std::move(model)};
}

/// The stand orientations for the design.
StandDesign chooseStands(const StandOptions& options, const FourierSeries& design) {
  StandTiltRequest request = options.request;
  request.design = design;
  StandDesign out;
  out.choice = chooseStandTilts(options.model, request);
  out.max_tilt = request.max_tilt;
  out.grid = request.tilt_grid;
  out.samples = request.samples;
  return out;
}
}  // namespace

int runExcite(const std::vector<std::string>& args) {
  po::options_description options("dynid excite");
  addRobotOptions(options);
  addStructuralOptions(options);
  addExciteOptions(options);
  po::variables_map vm;
  const std::string usage =
      "dynid excite --robot R [--drives] [--criterion cond|cond-unscaled|d-optimal|gc|relative-sd] "
      "[--period "
      "T] "
      "[--harmonics H] [limits] [--stands K [--max-tilt R]] [--seed S] --out DIR\n"
      "       dynid excite --robot R.urdf --floating-base --contacts FEET --stance Q1,...,Qn "
      "[--max-sway M] [--max-turn R] [--friction-cone MU] [--sensors SET] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  if (vm["floating-base"].as<bool>()) return runFloatingExcite(vm);
  refuseFloatingOptions(vm, {"contacts", "sensors", "motion", "stance", "max-sway", "max-turn",
                             "joint-margin", "max-swing", "friction-cone", "sole"});
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);  // before the work, not after it

  ExciteRequest request;
  request.criterion = parseOption(vm, "criterion", parseExcitationCriterion);
  request.period = vm["period"].as<double>();
  request.harmonics = vm["harmonics"].as<int>();
  request.starts = vm["starts"].as<int>();
  request.evaluations = vm["evaluations"].as<int>();
  if (const double s = vm["budget-seconds"].as<double>(); s > 0.0) request.max_seconds = s;
  request.grid_rate = vm["grid-rate"].as<double>();
  request.check_rate = vm["check-rate"].as<double>();
  request.torque_noise = vm["torque-noise"].as<double>();
  request.gc_segments = vm["segments"].as<int>();
  request.gc_horizon = vm["horizon"].as<double>();
  request.seed = vm["seed"].as<std::uint64_t>();  // --seed (structural options): also the starts
  request.threads = threadsOption(vm);
  request.structural = structuralOptions(vm);
  request.robot = loadRobotFromOptions(vm);
  const int n = request.robot.numJoints();
  applyPayloadOptions(vm, request);
  request.offset = optionalJointVector(vm, "offset", n, true);
  applyLimitOptions(vm, request);
  const std::optional<StandOptions> stand = standOptions(vm, request);
  const InterruptGuard guard;
  request.control.stop = guard.flag();
  if (stderrIsTerminal())
    request.control.progress = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
    };
  std::optional<ExciteOutcome> run;
  try {
    run.emplace(exciteRun(request));
  } catch (const Error&) {
    if (!guard.interrupted()) throw;
    std::cerr << "dynid excite: interrupted (Ctrl-C) before any design met the limits: nothing "
                 "written\n";
    return kExitInterrupted;
  }
  const ExciteOutcome& outcome = *run;
  ExcitationSettings settings;
  settings.robot = vm["robot"].as<std::string>();
  settings.source = modelSourceOf(settings.robot);
  settings.harmonics = request.harmonics;
  settings.starts = static_cast<int>(outcome.starts.size());  // 0 resolved
  settings.evaluations = request.evaluations;
  settings.period = request.period;
  settings.csv_rate = vm["csv-rate"].as<double>();
  if (stand && !guard.interrupted()) settings.stand = chooseStands(*stand, outcome.design);
  std::cout << writeExcitation(dir, request.robot, settings, outcome);
  if (stand && guard.interrupted())
    std::cerr << "dynid excite: interrupted before the stand orientations were chosen: "
                 "excitation.json's stand is null (run excite again with --stands)\n";
  return exitAfter(guard, "excite", "wrote the best design so far to " + dir);
}

}  // namespace dynid::cli
