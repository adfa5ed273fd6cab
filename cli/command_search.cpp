// dynid search: the paper's GC-error estimators (NLO, GA, hybrid).
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/search_output.hpp"
#include "core/parameters.hpp"
#include "core/perturb.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"
#include "search/optimizers.hpp"

namespace dynid::cli {

namespace {

using nlohmann::json;

std::atomic<bool> interrupted{false};
extern "C" void onInterrupt(int) { interrupted.store(true); }

/// The settings a checkpoint must share with the run that resumes it: all but the budgets and the
/// tolerance, which only decide when to stop (so a run can be resumed with a larger budget).
json fingerprint(json settings) {
  for (const char* key : {"budget_evaluations", "budget_seconds", "gc_tolerance"})
    settings.erase(key);
  return settings;
}

json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }
Eigen::VectorXd vectorFrom(const json& j) {
  const std::vector<double> v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

json historyJson(const std::vector<HistoryEntry>& history) {
  json out = json::array();
  for (const HistoryEntry& h : history)
    out.push_back({{"stage", h.stage},
                   {"iteration", h.iteration},
                   {"best_gc_error", h.best_gc},
                   {"best_parameter_error", numberOrNull(h.best_parameter_error)},
                   {"min_parameter_error", numberOrNull(h.min_parameter_error)},
                   {"evaluations", h.evaluations},
                   {"seconds", h.seconds}});
  return out;
}

std::vector<HistoryEntry> historyFrom(const json& j) {
  std::vector<HistoryEntry> out;
  for (const json& e : j) {
    HistoryEntry h;
    h.stage = e["stage"];
    h.iteration = e["iteration"];
    h.best_gc = e["best_gc_error"];
    h.best_parameter_error =
        e["best_parameter_error"].is_null() ? NAN : e["best_parameter_error"].get<double>();
    h.min_parameter_error =
        e["min_parameter_error"].is_null() ? NAN : e["min_parameter_error"].get<double>();
    h.evaluations = e["evaluations"];
    h.seconds = e["seconds"];
    out.push_back(h);
  }
  return out;
}

json stateJson(const SearchState& s, const json& settings) {
  json population = json::array();
  for (const Eigen::VectorXd& x : s.population) population.push_back(vectorJson(x));
  return {{"schema_version", 1},
          {"kind", "dynid.search_checkpoint"},
          {"settings", settings},
          {"method", s.method},
          {"stage", s.stage},
          {"iteration", s.iteration},
          {"rng", s.rng},
          {"best_x", vectorJson(s.best_x)},
          {"best_gc", s.best_gc},
          {"initial_gc", numberOrNull(s.initial_gc)},
          {"population", population},
          {"population_gc", s.population_gc},
          {"evaluations", s.evaluations},
          {"seconds", s.seconds},
          {"history", historyJson(s.history)}};
}

SearchState stateFrom(const json& j, const std::string& file) {
  try {
    SearchState s;
    s.method = j.at("method");
    s.stage = j.at("stage");
    s.iteration = j.at("iteration");
    s.rng = j.at("rng");
    s.best_x = vectorFrom(j.at("best_x"));
    s.best_gc = j.at("best_gc");
    s.initial_gc = j.at("initial_gc").is_null() ? NAN : j.at("initial_gc").get<double>();
    for (const json& x : j.at("population")) s.population.push_back(vectorFrom(x));
    s.population_gc = j.at("population_gc").get<std::vector<double>>();
    s.evaluations = j.at("evaluations");
    s.seconds = j.at("seconds");
    s.history = historyFrom(j.at("history"));
    return s;
  } catch (const json::exception& e) {
    throw ParseError(file, 0, "", std::string("not a dynid search checkpoint: ") + e.what());
  }
}

}  // namespace

int runSearch(const std::vector<std::string>& args) {
  po::options_description options("dynid search");
  addRobotOptions(options);
  options.add_options()("method", po::value<std::string>()->required(),
                        "nlo (multistart COBYLA), ga or hybrid")(
      "data", po::value<std::string>()->required(), "training dataset CSV")(
      "init", po::value<std::string>(), "initial estimate: a robot spec (puma560, .urdf, .json)")(
      "perturb", po::value<double>(),
      "initial estimate: the robot's parameters perturbed uniformly by up to this fraction")(
      "truth", po::value<std::string>(), "true model (robot spec), for parameter errors")(
      "validate", po::value<std::string>(), "held-out dataset CSV: its GC error before and after")(
      "seed", po::value<std::uint64_t>()->default_value(1), "seed of every random choice")(
      "threads", po::value<int>()->default_value(0), "worker threads (0: all cores)")(
      "budget-evals", po::value<long>()->default_value(0), "stop after this many GC evaluations")(
      "budget-seconds", po::value<double>()->default_value(0.0), "stop after this wall time [s]")(
      "gc-tolerance", po::value<double>()->default_value(0.0), "stop at this GC error")(
      "form", po::value<std::string>()->default_value("paper"),
      "paper (7 per link) or standard (10)")("range", po::value<double>()->default_value(0.5),
                                             "bounds: initial estimate +- this fraction")(
      "absolute-range", po::value<double>()->default_value(0.0),
      "range of parameters whose initial estimate is 0 (0: they stay fixed)")(
      "fix", po::value<std::string>(), "parameters held at their initial estimate, e.g. m2,cx3")(
      "mass-constraint", po::value<std::string>()->default_value("auto"),
      "on, off or auto (on for nlo and hybrid, off for ga, as in the paper)")(
      "total-mass", po::value<double>(),
      "total mass [kg] (default: the truth's, else the initial's)")(
      "horizon", po::value<double>()->default_value(0.05), "prediction horizon [s]")(
      "segments", po::value<int>()->default_value(100), "segments (0: all non-overlapping)")(
      "random-segments", po::bool_switch(), "seeded random segment starts")(
      "integrator", po::value<std::string>()->default_value("rk4"), "rk4 or euler (as the data)")(
      "step", po::value<double>()->default_value(0.0), "integration step [s] (0: sample period)")(
      "normalise", po::bool_switch(), "weight q and dq errors by 1 / their spread")(
      "population", po::value<int>()->default_value(100), "GA population")(
      "elites", po::value<int>()->default_value(1), "GA elites")(
      "migration", po::value<double>()->default_value(0.05), "GA migration factor")(
      "mutation-rate", po::value<double>()->default_value(0.1), "GA per-parameter mutation rate")(
      "mutation-scale", po::value<double>()->default_value(0.1), "mutation sigma / |value|")(
      "evals-per-seed", po::value<int>()->default_value(400), "NLO COBYLA evaluations per seed")(
      "checkpoint", po::value<std::string>(),
      "save after every round or generation; resume if it exists")(
      "out", po::value<std::string>()->required(), "output directory (search.json)");
  po::variables_map vm;
  const std::string usage =
      "dynid search --method nlo|ga|hybrid --robot R --data train.csv [--init guess.json | "
      "--perturb 0.3] [--truth truth.json] --seed S [--budget-evals N] [--budget-seconds T] --out "
      "DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const std::string method = vm["method"].as<std::string>();
  if (method != "nlo" && method != "ga" && method != "hybrid")
    throw UsageError("--method must be nlo, ga or hybrid, not '" + method + "'");
  if (vm.count("init") && vm.count("perturb"))
    throw UsageError("give --init or --perturb, not both");
  const long budget_evals = vm["budget-evals"].as<long>();
  double budget_seconds = vm["budget-seconds"].as<double>();
  if (budget_evals < 0 || budget_seconds < 0) throw UsageError("budgets must be >= 0");
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0 (0: all cores)");
  if (budget_evals == 0 && budget_seconds == 0 && vm["gc-tolerance"].as<double>() <= 0)
    budget_seconds = 60.0;  // never run unbounded
  const std::string mass = vm["mass-constraint"].as<std::string>();
  if (mass != "on" && mass != "off" && mass != "auto")
    throw UsageError("--mass-constraint must be on, off or auto");
  SegmentOptions segments;
  try {
    segments.integrator = parseIntegrator(vm["integrator"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(std::string("--integrator: ") + e.what());
  }
  segments.horizon = vm["horizon"].as<double>();
  segments.num_segments = vm["segments"].as<int>();
  segments.random_starts = vm["random-segments"].as<bool>();
  segments.seed = vm["seed"].as<std::uint64_t>();
  segments.step = vm["step"].as<double>();
  segments.normalise = vm["normalise"].as<bool>();

  const Model robot = loadRobotFromOptions(vm);
  const RobotOptions robot_options{vm["drives"].as<bool>(), vm["strict"].as<bool>()};
  Model initial = robot;
  if (vm.count("init")) initial = loadRobot(vm["init"].as<std::string>(), robot_options);
  if (vm.count("perturb"))
    initial = perturbedModel(robot, vm["perturb"].as<double>(), vm["seed"].as<std::uint64_t>());
  std::optional<Model> truth;
  if (vm.count("truth")) truth = loadRobot(vm["truth"].as<std::string>(), robot_options);
  for (const Model* m : {&initial, truth ? &*truth : nullptr})
    if (m != nullptr && (m->numJoints() != robot.numJoints() || m->parents != robot.parents))
      throw InputError("the initial and true models must have the robot's kinematic structure");

  SpaceOptions space_options;
  try {
    space_options.form = parseParameterForm(vm["form"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(std::string("--form: ") + e.what());
  }
  space_options.relative_range = vm["range"].as<double>();
  if (vm.count("fix")) {
    const std::string list = vm["fix"].as<std::string>();
    for (std::size_t start = 0; start <= list.size();) {
      const std::size_t comma = std::min(list.find(',', start), list.size());
      if (comma > start) space_options.fixed.push_back(list.substr(start, comma - start));
      start = comma + 1;
    }
  }
  space_options.absolute_range = vm["absolute-range"].as<double>();
  space_options.total_mass_constraint = mass == "on" || (mass == "auto" && method != "ga");
  auto total = [](const Model& m) {
    double t = 0.0;
    for (const auto& inertia : m.inertias) t += inertia.mass;
    return t;
  };
  space_options.total_mass =
      vm.count("total-mass") ? vm["total-mass"].as<double>() : total(truth ? *truth : initial);
  const ParameterSpace space(initial, space_options);
  const std::string data_file = vm["data"].as<std::string>();
  const GcProblem problem = makeGcProblem(readDatasetCsv(data_file, robot.numJoints()), segments);
  ThreadPool pool(vm["threads"].as<int>());
  Eigen::VectorXd truth_full;
  if (truth) truth_full = space.fullVector(*truth);

  json settings = {{"form", parameterFormName(space_options.form)},
                   {"free_parameters", space.freeNames()},
                   {"range", space_options.relative_range},
                   {"absolute_range", space_options.absolute_range},
                   {"mass_constraint", space_options.total_mass_constraint},
                   {"total_mass", space_options.total_mass},
                   {"horizon", segments.horizon},
                   {"segments", problem.numSegments()},
                   {"random_segments", segments.random_starts},
                   {"integrator", integratorName(segments.integrator)},
                   {"step", problem.step},
                   {"normalise", segments.normalise},
                   {"seed", vm["seed"].as<std::uint64_t>()},
                   {"budget_evaluations", budget_evals},
                   {"budget_seconds", budget_seconds},
                   {"gc_tolerance", vm["gc-tolerance"].as<double>()},
                   {"population", vm["population"].as<int>()},
                   {"elites", vm["elites"].as<int>()},
                   {"migration", vm["migration"].as<double>()},
                   {"mutation_rate", vm["mutation-rate"].as<double>()},
                   {"mutation_scale", vm["mutation-scale"].as<double>()},
                   {"evaluations_per_seed", vm["evals-per-seed"].as<int>()},
                   {"data", data_file}};
  // Checkpoints resume only runs with the same settings (threads may differ: results do not).
  std::optional<SearchState> resume;
  const std::string checkpoint = vm.count("checkpoint") ? vm["checkpoint"].as<std::string>() : "";
  if (!checkpoint.empty() && std::filesystem::exists(checkpoint)) {
    json saved;
    try {
      saved = json::parse(readFile(checkpoint));
    } catch (const json::parse_error& e) {
      throw ParseError(checkpoint, 0, "", std::string("invalid JSON: ") + e.what());
    }
    if (!saved.contains("settings") || saved["settings"] != fingerprint(settings) ||
        saved.value("method", "") != method)
      throw InputError(checkpoint +
                       ": the checkpoint was written with other settings; remove it "
                       "to start afresh");
    resume = stateFrom(saved, checkpoint);
  }

  SearchContext context;
  context.space = &space;
  context.problem = &problem;
  context.pool = &pool;
  context.truth_full = truth ? &truth_full : nullptr;
  context.budget = {budget_evals, budget_seconds, vm["gc-tolerance"].as<double>()};
  context.seed = vm["seed"].as<std::uint64_t>();
  context.stop = &interrupted;
  context.resume = resume ? &*resume : nullptr;
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  context.on_iteration = [&](const SearchState& state) {
    if (!checkpoint.empty())
      writeFileAtomically(checkpoint, stateJson(state, fingerprint(settings)).dump() + "\n");
    if (terminal && !state.history.empty()) {
      const HistoryEntry& h = state.history.back();
      std::fprintf(stderr, "\r[%s] %s %d: GC error %.4g (initial %.4g), %ld evaluations, %.1f s   ",
                   method.c_str(), h.stage == "ga" ? "generation" : "round", h.iteration, h.best_gc,
                   state.initial_gc, h.evaluations, h.seconds);
    }
  };
  NloOptions nlo;
  nlo.evaluations_per_seed = vm["evals-per-seed"].as<int>();
  nlo.mutation_scale = vm["mutation-scale"].as<double>();
  GaOptions ga;
  ga.population = vm["population"].as<int>();
  ga.elites = vm["elites"].as<int>();
  ga.migration = vm["migration"].as<double>();
  ga.mutation_rate = vm["mutation-rate"].as<double>();
  ga.mutation_scale = vm["mutation-scale"].as<double>();

  interrupted.store(false);
  auto previous = std::signal(SIGINT, onInterrupt);
  SearchResult result;
  try {
    result = method == "nlo"  ? runNlo(context, nlo)
             : method == "ga" ? runGa(context, ga)
                              : runHybrid(context, ga, nlo);
  } catch (...) {
    std::signal(SIGINT, previous);
    throw;
  }
  std::signal(SIGINT, previous);
  if (terminal) std::fprintf(stderr, "\n");

  json report = {{"schema_version", 1},
                 {"method", method},
                 {"robot", robot.name},
                 {"settings", settings},
                 {"termination", result.termination},
                 {"initial_gc_error", result.initial_gc},
                 {"final_gc_error", result.best_gc},
                 {"estimate", searchEstimateJson(space, result.best_x)},
                 {"initial_estimate", searchEstimateJson(space, space.project(space.initial()))},
                 {"history", historyJson(result.history)},
                 {"evaluations", result.evaluations},
                 {"seconds", result.seconds}};
  if (truth) {
    report["initial_parameter_error"] =
        space.parameterError(space.project(space.initial()), truth_full);
    report["final_parameter_error"] = space.parameterError(result.best_x, truth_full);
    json evaluated = json::array();
    for (const auto& [gc, pe] : result.evaluated) evaluated.push_back({gc, pe});
    report["evaluated"] = {{"columns", {"gc_error", "parameter_error"}}, {"rows", evaluated}};
  }
  if (vm.count("validate")) {
    const std::string file = vm["validate"].as<std::string>();
    const GcProblem test = makeGcProblem(readDatasetCsv(file, robot.numJoints()), segments);
    GcWorkspace workspace(robot, pool.numThreads());
    report["validation"] = {
        {"file", file},
        {"initial_gc_error",
         gcError(space.modelAt(space.project(space.initial())), test, workspace, pool)},
        {"final_gc_error", gcError(space.modelAt(result.best_x), test, workspace, pool)}};
  }
  const std::string dir = vm["out"].as<std::string>();
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir + "/search.json", report.dump(1) + "\n");
  std::cout << robot.name << " " << method << ": GC error " << result.initial_gc << " -> "
            << result.best_gc << " (" << result.initial_gc / std::max(result.best_gc, 1e-300)
            << "x lower) in " << result.evaluations << " evaluations, " << result.seconds << " s ("
            << result.termination << ")";
  if (report.contains("validation"))
    std::cout << "; held-out " << report["validation"]["initial_gc_error"].get<double>() << " -> "
              << report["validation"]["final_gc_error"].get<double>();
  std::cout << "\nwrote " << dir << "/search.json\n";
  return kExitOk;
}

}  // namespace dynid::cli
