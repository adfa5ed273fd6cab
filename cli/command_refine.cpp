// dynid refine: Ceres least squares on the GC residuals, from a search or identify result.
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/identification_output.hpp"
#include "cli/search_output.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "identifiability/base_parameters.hpp"
#include "search/refine.hpp"

namespace dynid::cli {

namespace {

using nlohmann::json;

std::atomic<bool> interrupted{false};
extern "C" void onRefineInterrupt(int) { interrupted.store(true); }

/// A standard vector from {name: value} (every name of the layout required).
Eigen::VectorXd standardFrom(const json& values, const std::vector<std::string>& names,
                             const std::string& file, const std::string& where) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (!values.contains(names[k]) || !values[names[k]].is_number())
      throw ParseError(file, 0, where + "." + names[k],
                       "missing or not a number (does --robot/--drives match the run?)");
    theta[static_cast<Eigen::Index>(k)] = values[names[k]].get<double>();
  }
  return theta;
}

}  // namespace

int runRefine(const std::vector<std::string>& args) {
  po::options_description options("dynid refine");
  addRobotOptions(options);
  options.add_options()("from", po::value<std::string>()->required(),
                        "start: DIR/search.json (dynid search) or DIR/estimate.json (identify)")(
      "data", po::value<std::string>()->required(), "training dataset CSV")(
      "validate", po::value<std::string>(), "held-out dataset CSV: its GC error before and after")(
      "truth", po::value<std::string>(), "true model (robot spec), for parameter errors")(
      "estimate-initial-states", po::bool_switch(),
      "estimate each segment's start state with the parameters (noisy measured starts)")(
      "continuity-weight", po::value<double>()->default_value(10.0),
      "with --estimate-initial-states: weight of the gap between a segment's predicted end and "
      "the next segment's start where they meet (contiguous segments, multiple shooting); 0 keeps "
      "the measured end states")("max-iterations", po::value<int>()->default_value(200),
                                 "Levenberg-Marquardt iterations per stage")(
      "no-base-stage", po::bool_switch(),
      "refine the free parameters directly, without first solving in base coordinates")(
      "no-gauge", po::bool_switch(),
      "let the directions that change no base parameter move (slower; for starts at a bound)")(
      "budget-seconds", po::value<double>()->default_value(0.0), "stop after this time (0: none)")(
      "threads", po::value<int>()->default_value(0), "threads (0: all cores)")(
      "form", po::value<std::string>()->default_value("paper"),
      "from estimate.json: paper or standard parameters")(
      "range", po::value<double>()->default_value(0.5),
      "from estimate.json: bounds, start +- this fraction")(
      "horizon", po::value<double>()->default_value(0.05),
      "from estimate.json: prediction horizon [s]")(
      "segments", po::value<int>()->default_value(100), "from estimate.json: segments")(
      "out", po::value<std::string>()->required(), "output directory (refine.json)");
  po::variables_map vm;
  const std::string usage =
      "dynid refine --robot R --from DIR/search.json|DIR/estimate.json --data train.csv "
      "[--estimate-initial-states] [--truth T] [--validate test.csv] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  if (vm["max-iterations"].as<int>() < 1) throw UsageError("--max-iterations must be >= 1");
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0 (0: all cores)");
  if (vm["budget-seconds"].as<double>() < 0) throw UsageError("--budget-seconds must be >= 0");
  if (!(vm["continuity-weight"].as<double>() >= 0.0) ||
      !std::isfinite(vm["continuity-weight"].as<double>()))
    throw UsageError("--continuity-weight must be a finite number >= 0");

  const Model robot = loadRobotFromOptions(vm);
  const RobotOptions robot_options{vm["drives"].as<bool>(), vm["strict"].as<bool>()};
  const std::string from = vm["from"].as<std::string>();
  json start;
  try {
    start = json::parse(readFile(from));
  } catch (const json::parse_error& e) {
    throw ParseError(from, 0, "", std::string("invalid JSON: ") + e.what());
  }
  const std::vector<std::string> names = standardParameterNames(robot.parameterLayout());
  const int threads = vm["threads"].as<int>() == 0
                          ? static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))
                          : vm["threads"].as<int>();

  // The search's space and segments (search.json), or the options' (estimate.json).
  SpaceOptions space_options;
  SegmentOptions segments;
  Model initial = robot, estimate = robot;
  std::string kind;
  try {
    if (start.contains("settings") && start.contains("estimate")) {
      kind = "search";
      const json& s = start.at("settings");
      space_options.form = parseParameterForm(s.at("form"));
      space_options.relative_range = s.at("range");
      space_options.absolute_range = s.at("absolute_range");
      space_options.total_mass_constraint = s.at("mass_constraint");
      space_options.total_mass = s.at("total_mass");
      segments.horizon = s.at("horizon");
      segments.num_segments = s.at("segments");
      segments.random_starts = s.at("random_segments");
      segments.seed = s.at("seed");
      segments.integrator = parseIntegrator(s.at("integrator"));
      segments.step = s.at("step");
      segments.normalise = s.at("normalise");
      initial.setStandardParameters(standardFrom(start.at("initial_estimate").at("standard"), names,
                                                 from, "initial_estimate.standard"));
      estimate.setStandardParameters(
          standardFrom(start.at("estimate").at("standard"), names, from, "estimate.standard"));
      // Free exactly what the search freed.
      const std::vector<std::string> free = s.at("free_parameters");
      const std::vector<std::string> all =
          space_options.form == ParameterForm::kPaper
              ? paperParameterNames(robot.numJoints())
              : standardParameterNames({robot.numJoints(), false, false});
      for (const std::string& name : all)
        if (std::find(free.begin(), free.end(), name) == free.end())
          space_options.fixed.push_back(name);
    } else if (start.contains("standard_estimate")) {
      kind = "estimate";
      space_options.form = parseParameterForm(vm["form"].as<std::string>());
      space_options.relative_range = vm["range"].as<double>();
      segments.horizon = vm["horizon"].as<double>();
      segments.num_segments = vm["segments"].as<int>();
      initial.setStandardParameters(standardFrom(start.at("standard_estimate").at("values"), names,
                                                 from, "standard_estimate.values"));
      estimate = initial;
    } else {
      throw ParseError(from, 0, "", "neither a dynid search.json nor an identify estimate.json");
    }
  } catch (const json::exception& e) {
    throw ParseError(from, 0, "", std::string("missing or malformed field: ") + e.what());
  }

  const ParameterSpace space(initial, space_options);
  const Eigen::VectorXd x0 = space.project(space.freeOf(space.fullVector(estimate)));
  const std::string data_file = vm["data"].as<std::string>();
  const GcProblem problem = makeGcProblem(readDatasetCsv(data_file, robot.numJoints()), segments);
  // Base coordinates from the structural analysis (the same defaults as dynid identifiability).
  const ParameterLayout layout = robot.parameterLayout();
  const BaseParameters base = computeBaseParameters(
      observationFromRandomStates(robot, std::max(100, 5 * layout.size() / robot.numJoints()), 1).W,
      names, 0.0, defaultPreference(layout.num_links, layout.perLink()));
  BaseCoordinates coordinates{base.projectionMatrix(), {}};
  for (int j = 0; j < base.numBase(); ++j) coordinates.names.push_back(base.baseName(j));

  RefineOptions refine;
  refine.estimate_initial_states = vm["estimate-initial-states"].as<bool>();
  refine.continuity_weight = vm["continuity-weight"].as<double>();
  refine.max_iterations = vm["max-iterations"].as<int>();
  refine.fix_gauge = !vm["no-gauge"].as<bool>();
  refine.base_stage = !vm["no-base-stage"].as<bool>();
  refine.max_seconds = vm["budget-seconds"].as<double>();
  refine.num_threads = threads;
  refine.stop = &interrupted;
  interrupted.store(false);
  auto previous = std::signal(SIGINT, onRefineInterrupt);
  RefineResult result;
  try {
    result = refineGc(space, problem, x0, refine, &coordinates);
  } catch (...) {
    std::signal(SIGINT, previous);
    throw;
  }
  std::signal(SIGINT, previous);

  json history = json::array();
  for (const RefineIteration& h : result.history)
    history.push_back({{"stage", h.stage},
                       {"iteration", h.iteration},
                       {"cost", h.cost},
                       {"gradient_max_norm", h.gradient_max_norm},
                       {"seconds", h.seconds}});
  const Eigen::VectorXd beta0 = base.project(space.standardAt(x0));
  json base_json = json::array();
  for (int j = 0; j < base.numBase(); ++j) {
    const double sd = result.beta_std_dev[j];
    base_json.push_back(
        {{"name", base.baseName(j)},
         {"expression", base.expression(j)},
         {"initial", beta0[j]},
         {"estimate", result.beta[j]},
         {"base_stage_estimate", numberOrNull(result.base_stage ? result.base_beta[j] : NAN)},
         {"std_dev", sd},
         {"confidence_95", {result.beta[j] - 1.96 * sd, result.beta[j] + 1.96 * sd}},
         {"relative_std_dev_percent",
          numberOrNull(result.beta[j] != 0.0 ? 100.0 * sd / std::abs(result.beta[j]) : INFINITY)}});
  }
  json covariance = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    covariance.push_back(std::vector<double>(result.beta_covariance.row(j).begin(),
                                             result.beta_covariance.row(j).end()));
  json free_directions = json::array();
  for (const FreeDirection& d : result.free_directions) {
    json combination = json::object();
    for (const auto& [name, coefficient] : d.combination) combination[name] = coefficient;
    free_directions.push_back(combination);
  }
  json report = {
      {"schema_version", 1},
      {"kind", "dynid.refine"},
      {"robot", robot.name},
      {"from", {{"file", from}, {"kind", kind}}},
      {"data", data_file},
      {"settings",
       {{"form", parameterFormName(space_options.form)},
        {"free_parameters", space.freeNames()},
        {"range", space_options.relative_range},
        {"mass_constraint", space_options.total_mass_constraint},
        {"total_mass", space_options.total_mass},
        {"horizon", segments.horizon},
        {"segments", problem.numSegments()},
        {"estimate_initial_states", refine.estimate_initial_states},
        {"continuity_weight", refine.continuity_weight},
        {"chained_segments", result.chained_segments},
        {"gauge", refine.fix_gauge},
        {"base_stage", refine.base_stage},
        {"max_iterations", refine.max_iterations},
        {"linear_solver", result.linear_solver}}},
      {"base_stage",
       {{"run", result.base_stage},
        {"gc_error", result.base_gc},
        {"iterations", result.base_iterations},
        {"termination", result.base_termination},
        {"map_back_error", result.map_back_error},
        {"map_back_used", result.map_back_used},
        {"note",
         "solved in base coordinates first, then the free parameters fitted to that beta within "
         "their bounds (map_back_error: RMS relative difference), then polished"}}},
      {"termination", result.termination},
      {"solution_usable", result.usable},
      {"interrupted", result.interrupted},
      {"iterations", result.iterations},
      {"seconds", result.seconds},
      {"initial_gc_error", result.initial_gc},
      {"final_gc_error", result.final_gc},
      {"cost_history", history},
      {"estimate", searchEstimateJson(space, result.x)},
      {"initial_estimate", searchEstimateJson(space, x0)},
      {"parameters_at_bound", result.at_bound},
      {"base_parameters",
       {{"values", base_json},
        {"covariance", covariance},
        {"residual_variance", result.sigma2},
        {"degrees_of_freedom", result.degrees_of_freedom},
        {"information_rank", result.information_rank},
        {"note",
         "covariance in base coordinates: sigma^2 (J_beta^T J_beta)^-1, the segment starts "
         "eliminated when estimated"}}},
      {"identifiability",
       {{"free_parameters", space.numFree()},
        {"base_directions_reachable", result.free_parameter_rank},
        {"gauge_dimension", result.gauge_dimension},
        {"free_directions", free_directions},
        {"note",
         "each free direction is a combination of free parameters that leaves every base "
         "parameter unchanged: the GC error cannot determine it"}}}};
  if (refine.estimate_initial_states) {
    Eigen::VectorXd shift(problem.numSegments());
    for (int s = 0; s < problem.numSegments(); ++s) {
      Eigen::VectorXd measured(2 * robot.numJoints());
      measured << problem.data.q.col(problem.starts[s]), problem.data.dq.col(problem.starts[s]);
      shift[s] = (result.initial_states.col(s) - measured).norm();
    }
    report["initial_states"] = {
        {"rms_shift_from_measured", std::sqrt(shift.squaredNorm() / problem.numSegments())}};
  }
  if (vm.count("truth")) {
    const Model truth = loadRobot(vm["truth"].as<std::string>(), robot_options);
    if (truth.parameterLayout().size() != layout.size())
      throw InputError("the true model has another parameter layout than the robot");
    const Eigen::VectorXd truth_full = space.fullVector(truth);
    const Eigen::VectorXd beta_true = base.project(truth.standardParameters());
    double initial_max = 0.0, final_max = 0.0;
    report["initial_parameter_error"] = space.parameterError(x0, truth_full);
    report["final_parameter_error"] = space.parameterError(result.x, truth_full);
    report["initial_base_parameter_error"] = baseParameterError(beta0, beta_true, &initial_max);
    report["final_base_parameter_error"] = baseParameterError(result.beta, beta_true, &final_max);
    report["final_base_parameter_error_max"] = final_max;
    if (result.base_stage)
      report["base_stage"]["base_parameter_error"] =
          baseParameterError(result.base_beta, beta_true);
  }
  if (vm.count("validate")) {
    const std::string file = vm["validate"].as<std::string>();
    const GcProblem test = makeGcProblem(readDatasetCsv(file, robot.numJoints()), segments);
    ThreadPool pool(threads);
    GcWorkspace workspace(robot, pool.numThreads());
    report["validation"] = {
        {"file", file},
        {"initial_gc_error", gcError(space.modelAt(x0), test, workspace, pool)},
        {"final_gc_error", gcError(space.modelAt(result.x), test, workspace, pool)}};
  }
  const std::string dir = vm["out"].as<std::string>();
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir + "/refine.json", report.dump(1) + "\n");
  std::cout << robot.name << " refine: GC error " << result.initial_gc << " -> " << result.final_gc
            << " in ";
  if (result.base_stage)
    std::cout << result.base_iterations << " + " << result.iterations
              << " iterations (base coordinates + parameters), ";
  else
    std::cout << result.iterations << " iterations, ";
  std::cout << result.seconds << " s ("
            << result.termination.substr(0, result.termination.find(':')) << ")";
  if (report.contains("final_base_parameter_error"))
    std::cout << "; base-parameter error " << report["initial_base_parameter_error"].get<double>()
              << " -> " << report["final_base_parameter_error"].get<double>();
  std::cout << "\nwrote " << dir << "/refine.json\n";
  return kExitOk;
}

}  // namespace dynid::cli
