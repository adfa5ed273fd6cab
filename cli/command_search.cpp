// dynid search: the paper's GC-error estimators (NLO, GA, hybrid).
#include <cstdio>
#include <iostream>

#include "analysis/records/provenance.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"
#include "reports/run_report.hpp"

namespace dynid::cli {

namespace {

/// The options, bound to the request's fields (po::notify stores them).
void addSearchOptions(po::options_description& options, SearchRequest& r) {
  options.add_options()("method", po::value<std::string>()->required(),
                        "nlo (multistart COBYLA), ga or hybrid")(
      "data", po::value(&r.data_file)->required(), "training dataset CSV")(
      "init", po::value<std::string>(), "initial estimate: a robot spec (puma560, .urdf, .json)")(
      "perturb", po::value<double>())("truth", po::value<std::string>(),
                                      "true model (robot spec), for parameter errors")(
      "validate", po::value(&r.validate_file),
      "held-out dataset CSV: its GC error before and after")(
      "seed", po::value(&r.seed)->default_value(r.seed), "seed of every random choice")(
      "budget-evals",
      po::value(&r.budget.max_evaluations)->default_value(r.budget.max_evaluations))(
      "budget-seconds", po::value(&r.budget.max_seconds)->default_value(r.budget.max_seconds))(
      "gc-tolerance", po::value(&r.budget.gc_tolerance)->default_value(r.budget.gc_tolerance))(
      "form", po::value<std::string>()->default_value("paper"),
      "paper (7 per link) or standard (10)")(
      "range", po::value(&r.space.relative_range)->default_value(r.space.relative_range))(
      "absolute-range", po::value(&r.space.absolute_range)->default_value(r.space.absolute_range))(
      "fix", po::value<std::string>(), "parameters held at their initial estimate, e.g. m2,cx3")(
      "mass-constraint", po::value(&r.mass_constraint)->default_value(r.mass_constraint),
      "on, off or auto (on for nlo and hybrid, off for ga, as in the paper)")("total-mass",
                                                                              po::value<double>())(
      "horizon", po::value(&r.segments.horizon)->default_value(r.segments.horizon))(
      "segments", po::value(&r.segments.num_segments)->default_value(r.segments.num_segments))(
      "random-segments", po::bool_switch(&r.segments.random_starts),
      "seeded random segment starts")("integrator", po::value<std::string>()->default_value("rk4"),
                                      "rk4 or euler (as the data)")(
      "step", po::value(&r.segments.step)->default_value(r.segments.step))(
      "normalise", po::bool_switch(&r.segments.normalise),
      "weight q and dq errors by 1 / their spread")(
      "population", po::value(&r.ga.population)->default_value(r.ga.population))(
      "elites", po::value(&r.ga.elites)->default_value(r.ga.elites))(
      "migration", po::value(&r.ga.migration)->default_value(r.ga.migration))(
      "mutation-rate", po::value(&r.ga.mutation_rate)->default_value(r.ga.mutation_rate))(
      "mutation-scale", po::value(&r.ga.mutation_scale)->default_value(r.ga.mutation_scale))(
      "evals-per-seed",
      po::value(&r.nlo.evaluations_per_seed)->default_value(r.nlo.evaluations_per_seed))(
      "checkpoint", po::value(&r.checkpoint),
      "save after every round or generation; resume if it exists")(
      "out", po::value<std::string>()->required(), "output directory (search.json)");
  addThreadsOption(options);
}

/// What the bound options leave: the parsed ones and the checks.
void readSearchSettings(const po::variables_map& vm, SearchRequest& r) {
  if (r.budget.max_evaluations < 0 || r.budget.max_seconds < 0)
    throw UsageError("budgets must be >= 0");
  if (r.mass_constraint != "on" && r.mass_constraint != "off" && r.mass_constraint != "auto")
    throw UsageError("--mass-constraint must be on, off or auto");
  r.segments.integrator = parseOption(vm, "integrator", parseIntegrator);
  r.space.form = parseOption(vm, "form", parseParameterForm);
  r.space.fixed = nameListOption(vm, "fix");
  if (vm.count("total-mass")) r.total_mass = vm["total-mass"].as<double>();
  r.threads = threadsOption(vm);
  r.nlo.mutation_scale = r.ga.mutation_scale;
}

}  // namespace

int runSearch(const std::vector<std::string>& args) {
  po::options_description options("dynid search");
  SearchRequest request;
  addRobotOptions(options);
  addSearchOptions(options, request);
  po::variables_map vm;
  const std::string usage =
      "dynid search --method nlo|ga|hybrid --robot R --data train.csv [--init guess.json | "
      "--perturb 0.3] [--truth truth.json] --seed S [--budget-evals N] [--budget-seconds T] --out "
      "DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  request.method = parseOption(
      vm, "method", [](const std::string& name) { return parseMethod(name, searchMethods()); });
  if (vm.count("init") && vm.count("perturb"))
    throw UsageError("give --init or --perturb, not both");
  const std::string method = methodName(request.method);
  refuseUnused(vm, request.method != Method::kNlo,
               {"population", "elites", "migration", "mutation-rate"},
               "applies to --method ga and hybrid, not " + method);
  refuseUnused(vm, request.method != Method::kGa, {"evals-per-seed"},
               "applies to --method nlo and hybrid, not " + method);
  readSearchSettings(vm, request);
  request.robot = loadRobotFromOptions(vm);
  request.robot_source = modelSourceOf(vm["robot"].as<std::string>());
  if (vm.count("init")) request.init = loadOtherRobot(vm, "init");
  if (vm.count("perturb")) request.perturb = vm["perturb"].as<double>();
  if (vm.count("truth")) request.truth = loadOtherRobot(vm, "truth");

  const InterruptGuard guard;
  request.control.stop = guard.flag();
  const bool terminal = stderrIsTerminal();
  // The budget the search will hold (searchRun's default of 60 s when none is given).
  SearchBudget budget = request.budget;
  if (budget.max_evaluations == 0 && budget.max_seconds == 0 && budget.gc_tolerance <= 0)
    budget.max_seconds = 60.0;
  if (terminal)
    request.on_iteration = [&](const SearchState& state) {
      std::fprintf(stderr, "\r%s", searchProgressLine(request.method, state, budget).c_str());
    };
  const SearchOutcome outcome = searchRun(request);
  if (terminal) std::fprintf(stderr, "\n");
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(dir, {{"search.json", jsonText(withProvenance(searchJson(outcome)), 1) + "\n"}});
  std::cout << searchSummary(outcome, dir);
  return exitAfter(guard, "search", "wrote the best parameters so far to " + dir + "/search.json");
}

}  // namespace dynid::cli
