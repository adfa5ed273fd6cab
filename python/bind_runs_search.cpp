// The runs wing's search rooms: simulate, gc_error, search and refine (analysis/runs/simulate.hpp,
// analysis/runs/search.hpp). Settings, defaults and results are the CLI's (same seed, same
// numbers); to_json() gives the document the CLI writes.
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/records/document.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/search.hpp"
#include "analysis/runs/simulate.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/dataset_csv.hpp"
#include "data/json_number.hpp"
#include "python/run_support.hpp"
#include "reports/identification_report.hpp"
#include "reports/run_report.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"

namespace dynid::python {
namespace {

// ---- simulate ----

Trajectory simulatePy(const Model& model, std::optional<double> duration, double dt, double rate,
                      const std::string& controller, const OptionalArrayLike& amplitude,
                      const OptionalArrayLike& q0, const OptionalArrayLike& frequency,
                      const OptionalArrayLike& phase, double base_frequency, int harmonics,
                      const OptionalArrayLike& kp, const OptionalArrayLike& kd,
                      const OptionalArrayLike& tau_max, double bandwidth,
                      const std::optional<Model>& controller_model, double controller_perturb,
                      const std::string& integrator, double noise_q, double noise_dq,
                      double noise_tau, std::uint64_t seed, const OptionalPathLike& trajectory,
                      const std::optional<std::vector<double>>& pauses, bool stiction) {
  if (controller != "sinusoidal" && controller != "fourier")
    throw py::value_error("controller: expected 'sinusoidal' or 'fourier', not '" + controller +
                          "'");
  const int n = model.numJoints();
  SimulateRequest r;
  r.robot = model;
  r.controller_model = controller_model;
  r.controller_perturb = controller_perturb;
  r.fourier = controller == "fourier";
  if (!trajectory.is_none()) r.trajectory = pathArg(trajectory, "trajectory");
  r.one_period = !trajectory.is_none() && !duration;
  r.q0 = jointOption(q0, "q0", n);
  r.amplitude = *jointOption(amplitude, "amplitude", n);
  r.frequency = jointOption(frequency, "frequency", n);
  r.phase = jointOption(phase, "phase", n);
  r.base_frequency = base_frequency;
  r.harmonics = harmonics;
  r.kp = jointOption(kp, "kp", n);
  r.kd = jointOption(kd, "kd", n);
  r.tau_max = jointOption(tau_max, "tau_max", n);
  r.bandwidth = bandwidth;
  SimulationOptions& s = r.simulation;
  s.duration = duration.value_or(SimulateRequest{}.simulation.duration);
  s.step = dt;
  s.record_rate = rate;
  s.integrator = parseIntegrator(integrator);
  s.noise_q = noise_q;
  s.noise_dq = noise_dq;
  s.noise_tau = noise_tau;
  s.seed = seed;
  s.stiction = stiction;
  if (pauses) {
    if (pauses->size() < 2 || pauses->size() > 3)
      throw py::value_error("pauses: expected (move, hold) or (move, hold, ramp) [s]");
    Pauses p;
    p.move = (*pauses)[0], p.hold = (*pauses)[1];
    if (pauses->size() == 3) p.ramp = (*pauses)[2];
    if (const std::string why = p.problem(); !why.empty()) throw py::value_error("pauses: " + why);
    r.pauses = p;
  }
  SimulateOutcome out;
  {
    py::gil_scoped_release release;
    out = simulateRun(r);
  }
  warnAll(out.warnings);  // a trajectory of an earlier version, read as it is
  return out.trajectory;
}

// ---- search ----

struct SearchPy {
  Model robot;
  SearchOutcome outcome;
  RunProvenance provenance;  // the call that made it
};

SearchPy searchPy(const Model& robot, const DataLike& data, const std::string& method,
                  const std::optional<Model>& init, const std::optional<double>& perturb,
                  const std::optional<Model>& truth, const OptionalPathLike& validate,
                  long budget_evals, double budget_seconds, double gc_tolerance,
                  const std::string& form, double range, double absolute_range,
                  const std::vector<std::string>& fix, const std::string& mass_constraint,
                  const std::optional<double>& total_mass, double horizon, int segments,
                  bool random_segments, const std::string& integrator, double step, bool normalise,
                  int population, int elites, double migration, double mutation_rate,
                  double mutation_scale, int evals_per_seed, std::uint64_t seed, int threads,
                  const std::string& checkpoint, const ProgressLike& progress) {
  if (init && perturb) throw py::value_error("give init or perturb, not both");
  const SearchRequest d;
  if (method == "nlo" && (population != d.ga.population || elites != d.ga.elites ||
                          migration != d.ga.migration || mutation_rate != d.ga.mutation_rate))
    throw py::value_error(
        "population, elites, migration and mutation_rate apply to 'ga' and 'hybrid', not 'nlo'");
  if (method == "ga" && evals_per_seed != d.nlo.evaluations_per_seed)
    throw py::value_error("evals_per_seed applies to 'nlo' and 'hybrid', not 'ga'");
  SearchRequest r;  // checked by searchRun
  r.robot = robot;
  r.method = parseMethod(method, searchMethods());
  r.init = init;
  r.perturb = perturb;
  r.truth = truth;
  const DataArg train = dataArg(data, "data", robot);
  r.data_file = train.path;
  r.data = train.arrays;
  if (!validate.is_none()) r.validate_file = pathArg(validate, "validate");
  r.budget.max_evaluations = budget_evals;
  r.budget.max_seconds = budget_seconds;
  r.budget.gc_tolerance = gc_tolerance;
  r.space.form = parseParameterForm(form);
  r.space.relative_range = range;
  r.space.absolute_range = absolute_range;
  r.space.fixed = fix;
  r.mass_constraint = mass_constraint;
  r.total_mass = total_mass;
  r.segments =
      segmentOptions(horizon, segments, random_segments, integrator, step, normalise, seed);
  r.ga.population = population;
  r.ga.elites = elites;
  r.ga.migration = migration;
  r.ga.mutation_rate = mutation_rate;
  r.ga.mutation_scale = mutation_scale;
  r.nlo.mutation_scale = mutation_scale;
  r.nlo.evaluations_per_seed = evals_per_seed;
  r.seed = seed;
  r.threads = threads;
  r.checkpoint = checkpoint;
  Interrupt interrupt;
  interrupt.setCallback(progress);
  r.control.stop = interrupt.flag();
  // The budget the search holds (searchRun's 60 s when none is given), for the share done.
  SearchBudget budget = r.budget;
  if (budget.max_evaluations == 0 && budget.max_seconds == 0 && budget.gc_tolerance <= 0)
    budget.max_seconds = 60.0;
  r.on_iteration = [&](const SearchState& state) {
    interrupt.report([&] {
      py::dict d;
      if (state.history.empty()) return d;
      const HistoryEntry& h = state.history.back();
      double done = 0.0;
      if (budget.max_seconds > 0.0) done = std::max(done, h.seconds / budget.max_seconds);
      if (budget.max_evaluations > 0)
        done = std::max(done, static_cast<double>(h.evaluations) / budget.max_evaluations);
      d["stage"] = h.stage;
      d["iteration"] = h.iteration;
      d["best_gc"] = h.best_gc;
      d["evaluations"] = h.evaluations;
      d["seconds"] = h.seconds;
      d["done"] = std::min(done, 1.0);
      d["line"] = searchProgressLine(r.method, state, budget);
      return d;
    });
  };
  SearchPy out{robot, {}, {}};
  const PythonRun call("search", {r.data_file, r.validate_file}, seed, threads);
  {
    py::gil_scoped_release release;
    out.outcome = searchRun(r);
  }
  out.provenance = call.finish();
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

// ---- refine ----

struct RefinePy {
  RefineOutcome outcome;
  RunProvenance provenance;  // the call that made it
};

RefinePy refinePy(const Model& robot, const StartLike& start, const DataLike& data,
                  const OptionalPathLike& validate, const std::optional<Model>& truth,
                  bool estimate_initial_states, double continuity_weight, int max_iterations,
                  bool base_stage, bool gauge, double budget_seconds, const std::string& form,
                  double range, double horizon, int segments, int threads,
                  const ProgressLike& progress) {
  RefineRequest r;  // checked by refineRun
  r.robot = robot;
  if (py::isinstance<SearchPy>(start)) {
    r.from_file = "<search>";
    r.from_document = searchJson(start.cast<const SearchPy&>().outcome);
  } else if (py::hasattr(start, "to_json") && !py::isinstance<py::str>(start)) {
    r.from_file = "<estimate>";  // an Estimate: its estimate.json
    r.from_document = parseJson(start.attr("to_json")().cast<std::string>(), r.from_file);
  } else {
    r.from_file = pathArg(start, "start");
  }
  const DataArg train = dataArg(data, "data", robot);
  r.data_file = train.path;
  r.data = train.arrays;
  if (!validate.is_none()) r.validate_file = pathArg(validate, "validate");
  r.truth = truth;
  RefineOptions& o = r.options;
  o.estimate_initial_states = estimate_initial_states;
  o.continuity_weight = continuity_weight;
  o.max_iterations = max_iterations;
  o.base_stage = base_stage;
  o.fix_gauge = gauge;
  o.max_seconds = budget_seconds;
  o.num_threads = threads;
  r.form = parseParameterForm(form);
  r.range = range;
  r.horizon = horizon;
  r.segments = segments;
  Interrupt interrupt;
  interrupt.setCallback(progress);
  r.control.stop = interrupt.flag();
  r.control.on_check = [&] { interrupt.poll(); };
  o.on_iteration = [&](const RefineIteration& it, double done) {
    interrupt.report([&] {
      py::dict d;
      d["stage"] = it.stage;
      d["iteration"] = it.iteration;
      d["cost"] = it.cost;
      d["seconds"] = it.seconds;
      d["done"] = std::clamp(done, 0.0, 1.0);
      d["line"] = "[refine] " + it.stage + " iteration " + std::to_string(it.iteration) +
                  ": cost " + formatNumber(it.cost, 4) + "; " + progressText(done, it.seconds);
      return d;
    });
  };
  RefinePy out;
  const PythonRun call("refine", {r.from_file, r.data_file, r.validate_file}, std::nullopt,
                       threads);
  {
    py::gil_scoped_release release;
    out.outcome = refineRun(r);
  }
  out.provenance = call.finish();
  warnAll(out.outcome.warnings);     // a start of an earlier version, read as it is
  out.outcome.options.control = {};  // it points into `interrupt`, gone on return
  out.outcome.options.on_iteration = nullptr;
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

void bindSimulate(py::module_& m) {
  m.def(
      "simulate", &simulatePy, py::arg("model"), py::arg("duration") = py::none(),
      py::arg("dt") = SimulateRequest{}.simulation.step,
      py::arg("rate") = SimulateRequest{}.simulation.record_rate,
      py::arg("controller") = "sinusoidal", py::arg("amplitude") = 0.5, py::arg("q0") = py::none(),
      py::arg("frequency") = py::none(), py::arg("phase") = py::none(),
      py::arg("base_frequency") = SimulateRequest{}.base_frequency,
      py::arg("harmonics") = SimulateRequest{}.harmonics, py::arg("kp") = py::none(),
      py::arg("kd") = py::none(), py::arg("tau_max") = py::none(),
      py::arg("bandwidth") = SimulateRequest{}.bandwidth, py::arg("controller_model") = py::none(),
      py::arg("controller_perturb") = SimulateRequest{}.controller_perturb,
      py::arg("integrator") = "rk4", py::arg("noise_q") = SimulateRequest{}.simulation.noise_q,
      py::arg("noise_dq") = SimulateRequest{}.simulation.noise_dq,
      py::arg("noise_tau") = SimulateRequest{}.simulation.noise_tau,
      py::arg("seed") = SimulateRequest{}.simulation.seed, py::arg("trajectory") = py::none(),
      py::arg("pauses") = py::none(), py::arg("stiction") = SimulateRequest{}.simulation.stiction,
      "`dynid simulate`: the robot under a tracking controller, returned as a Dataset. "
      "Per-joint settings take one number or n; trajectory: an excitation.json design, one period "
      "unless duration is given (default duration: 10 s); pauses: (move, hold[, ramp]) [s], stops "
      "in the motion as simulate --pauses; stiction: a joint at zero velocity sticks while its "
      "static friction can hold it, as simulate --stiction (default: its friction law's value).");

  m.def(
      "gc_error",
      [](const Model& model, const DataLike& data, double horizon, int segments,
         bool random_segments, const std::string& integrator, double step, bool normalise,
         std::uint64_t seed, int threads) {
        checkThreads(threads);
        const DataArg d = dataArg(data, "data", model);
        const SegmentOptions options =
            segmentOptions(horizon, segments, random_segments, integrator, step, normalise, seed);
        const Model local = model;
        py::gil_scoped_release release;
        const GcProblem problem = makeGcProblem(trajectoryOf(d, local), options);
        ThreadPool pool(resolveThreads(threads));
        GcWorkspace workspace(pool.numThreads());
        return gcError(local, problem, workspace, pool);
      },
      py::arg("model"), py::arg("data"), py::arg("horizon") = SegmentOptions{}.horizon,
      py::arg("segments") = SegmentOptions{}.num_segments, py::arg("random_segments") = false,
      py::arg("integrator") = "rk4", py::arg("step") = SegmentOptions{}.step,
      py::arg("normalise") = false, py::arg("seed") = SegmentOptions{}.seed,
      py::arg("threads") = kAllThreads,
      "The paper's GC error of the model on `data`: the summed squared error of (q, dq) "
      "predicted `horizon` seconds ahead from each segment's measured start, as `dynid search` "
      "evaluates it (the same number for any thread count).");
}

void bindSearchRuns(py::module_& m) {
  py::class_<SearchPy>(m, "Search", "What `dynid search` writes as search.json.")
      .def_property_readonly(
          "method", [](const SearchPy& s) { return std::string(methodName(s.outcome.method)); },
          "The optimiser, 'nlo' (multistart COBYLA) or 'ga' (genetic algorithm).")
      .def_property_readonly(
          "termination", [](const SearchPy& s) { return s.outcome.result.termination; },
          "Why the search stopped (budget, tolerance, interrupted).")
      .def_property_readonly(
          "initial_gc", [](const SearchPy& s) { return s.outcome.result.initial_gc; },
          "The GC error of the starting parameters.")
      .def_property_readonly(
          "best_gc", [](const SearchPy& s) { return s.outcome.result.best_gc; },
          "The lowest GC error found.")
      .def_property_readonly(
          "evaluations", [](const SearchPy& s) { return s.outcome.result.evaluations; },
          "The number of GC error evaluations.")
      .def_property_readonly(
          "free_names", [](const SearchPy& s) { return s.outcome.space->freeNames(); },
          "The searched (free) parameters' names, in the order of best_x.")
      .def_property_readonly(
          "best_x", [](const SearchPy& s) { return toNumpy(s.outcome.result.best_x); },
          "The best free parameters (free_names order).")
      .def_property_readonly(
          "model",
          [](const SearchPy& s) { return s.outcome.space->modelAt(s.outcome.result.best_x); },
          "The robot with the best parameters.")
      .def_property_readonly(
          "initial_parameter_error",
          [](const SearchPy& s) { return s.outcome.initial_parameter_error; },
          "The starting parameters' relative error against truth= (None without it).")
      .def_property_readonly(
          "final_parameter_error",
          [](const SearchPy& s) { return s.outcome.final_parameter_error; },
          "The best parameters' relative error against truth= (None without it).")
      .def_property_readonly(
          "history",
          [](const SearchPy& s) {
            py::list out;
            for (const HistoryEntry& h : s.outcome.result.history) {
              py::dict d;
              d["stage"] = h.stage;
              d["iteration"] = h.iteration;
              d["best_gc"] = h.best_gc;
              d["best_parameter_error"] = h.best_parameter_error;
              d["evaluations"] = h.evaluations;
              out.append(d);
            }
            return out;
          },
          "One dict per round (stage, iteration, best_gc, best_parameter_error, ...).")
      .def(
          "to_json",
          [](const SearchPy& s) {
            return jsonText(withCall(searchJson(s.outcome), s.provenance), 1) + "\n";
          },
          "search.json, as `dynid search` writes it.");

  m.def("search", &searchPy, py::arg("robot"), py::arg("data"), py::arg("method"),
        py::arg("init") = py::none(), py::arg("perturb") = py::none(),
        py::arg("truth") = py::none(), py::arg("validate") = py::none(),
        py::arg("budget_evals") = SearchRequest{}.budget.max_evaluations,
        py::arg("budget_seconds") = SearchRequest{}.budget.max_seconds,
        py::arg("gc_tolerance") = SearchRequest{}.budget.gc_tolerance, py::arg("form") = "paper",
        py::arg("range") = SearchRequest{}.space.relative_range,
        py::arg("absolute_range") = SearchRequest{}.space.absolute_range,
        py::arg("fix") = std::vector<std::string>{}, py::arg("mass_constraint") = "auto",
        py::arg("total_mass") = py::none(), py::arg("horizon") = SearchRequest{}.segments.horizon,
        py::arg("segments") = SearchRequest{}.segments.num_segments,
        py::arg("random_segments") = false, py::arg("integrator") = "rk4",
        py::arg("step") = SearchRequest{}.segments.step, py::arg("normalise") = false,
        py::arg("population") = SearchRequest{}.ga.population,
        py::arg("elites") = SearchRequest{}.ga.elites,
        py::arg("migration") = SearchRequest{}.ga.migration,
        py::arg("mutation_rate") = SearchRequest{}.ga.mutation_rate,
        py::arg("mutation_scale") = SearchRequest{}.ga.mutation_scale,
        py::arg("evals_per_seed") = SearchRequest{}.nlo.evaluations_per_seed,
        py::arg("seed") = SearchRequest{}.seed, py::arg("threads") = kAllThreads,
        py::arg("checkpoint") = "", py::arg("progress") = py::none(),
        "`dynid search`: the GC-error search 'nlo' (multistart COBYLA), 'ga' or 'hybrid' from "
        "init (a Model) or the robot perturbed by `perturb`; the same options and defaults as "
        "the CLI, and for the same seed the same result whatever the thread count. Ctrl-C stops "
        "it with the best result so far (and a warning). progress: a callable given a dict "
        "(stage, iteration, best_gc, evaluations, seconds, done: the share of the budget, line: "
        "the CLI's progress line) after every round or generation; returning False stops the "
        "search with its best result so far, an exception stops it and is raised.");
}

void bindRefine(py::module_& m) {
  py::class_<RefinePy>(m, "Refinement", "What `dynid refine` writes as refine.json.")
      .def_property_readonly(
          "initial_gc", [](const RefinePy& r) { return r.outcome.result.initial_gc; },
          "The GC error at the start.")
      .def_property_readonly(
          "final_gc", [](const RefinePy& r) { return r.outcome.result.final_gc; },
          "The GC error at the end.")
      .def_property_readonly(
          "termination", [](const RefinePy& r) { return r.outcome.result.termination; },
          "Why the refinement stopped (Ceres' reason, the budget or an interrupt).")
      .def_property_readonly(
          "x", [](const RefinePy& r) { return toNumpy(r.outcome.result.x); },
          "The refined free parameters, in the order of free_names.")
      .def_property_readonly(
          "free_names", [](const RefinePy& r) { return r.outcome.space->freeNames(); },
          "The refined (free) parameters' names.")
      .def_property_readonly(
          "model", [](const RefinePy& r) { return r.outcome.space->modelAt(r.outcome.result.x); },
          "The robot with the refined parameters.")
      .def_property_readonly(
          "final_parameter_error",
          [](const RefinePy& r) -> std::optional<double> {
            if (!r.outcome.has_truth) return std::nullopt;
            return r.outcome.final_parameter_error;
          },
          "The refined parameters' relative error against truth= (None without it).")
      .def_property_readonly(
          "final_base_error",
          [](const RefinePy& r) -> std::optional<double> {
            if (!r.outcome.has_truth) return std::nullopt;
            return r.outcome.final_base_error;
          },
          "The refined base parameters' relative error against truth= (None without it).")
      .def(
          "to_json",
          [](const RefinePy& r) {
            return jsonText(withCall(refineJson(r.outcome), r.provenance), 1) + "\n";
          },
          "refine.json, as `dynid refine` writes it.");

  m.def("refine", &refinePy, py::arg("robot"), py::arg("start"), py::arg("data"),
        py::arg("validate") = py::none(), py::arg("truth") = py::none(),
        py::arg("estimate_initial_states") = false,
        py::arg("continuity_weight") = RefineRequest{}.options.continuity_weight,
        py::arg("max_iterations") = RefineRequest{}.options.max_iterations,
        py::arg("base_stage") = true, py::arg("gauge") = true,
        py::arg("budget_seconds") = RefineRequest{}.options.max_seconds, py::arg("form") = "paper",
        py::arg("range") = RefineRequest{}.range, py::arg("horizon") = RefineRequest{}.horizon,
        py::arg("segments") = RefineRequest{}.segments, py::arg("threads") = kAllThreads,
        py::arg("progress") = py::none(),
        "`dynid refine`: Ceres (Levenberg-Marquardt) on the GC residuals from `start`: a "
        "Search, an Estimate, or the path of a search.json or estimate.json. form, range, "
        "horizon and segments apply to an estimate start (a search carries its own). "
        "progress(info) is called after every iteration with a dict (stage, iteration, cost, "
        "seconds, done: the share of the budget or of max_iterations, line: the CLI's); "
        "returning False stops the refinement with its best parameters so far.");
}

}  // namespace

void bindRunsSearch(py::module_& m) {
  bindSimulate(m);
  bindSearchRuns(m);
  bindRefine(m);
}

}  // namespace dynid::python
