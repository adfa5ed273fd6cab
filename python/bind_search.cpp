// The paper's machinery and the data pipelines: simulate, gc_error, search, refine, excite,
// prepare. Settings, defaults and results are the CLI's (same seed, same numbers); to_json()
// gives the document the CLI writes.
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

#include <pybind11/stl.h>

#include <tuple>

#include "analysis/excitation/excite.hpp"
#include "analysis/logs/prepare.hpp"
#include "analysis/logs/read_log.hpp"
#include "analysis/records/document.hpp"
#include "analysis/runs.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/integrators.hpp"
#include "data/bags/bag.hpp"
#include "data/dataset_csv.hpp"
#include "data/json_number.hpp"
#include "python/common.hpp"
#include "reports/excitation_report.hpp"
#include "reports/identification_report.hpp"
#include "reports/prepare_report.hpp"
#include "reports/run_report.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"

namespace dynid::python {
namespace {

/// Lets Ctrl-C stop a long run cleanly: each progress step takes the GIL and runs Python's signal
/// handlers; a KeyboardInterrupt sets the stop flag (the run returns its best result so far,
/// termination "interrupted") and is reported as a warning once the run has returned.
class Interrupt {
 public:
  const std::atomic<bool>* flag() const { return &stop_; }
  void poll() {
    if (stop_) return;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      stop_ = true;
    }
  }
  void warnIfStopped() const {
    if (stop_) PyErr_WarnEx(PyExc_UserWarning, "interrupted: the result is the best one so far", 1);
  }
  /// A user's progress callback (None: none), called with a dict at every progress step; its
  /// returning False stops the run as Ctrl-C does (the best result so far is returned).
  void setCallback(const py::object& callback) {
    if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
      throw py::type_error("progress: expected a callable taking a dict, or None");
    callback_ = callback;
  }
  /// Polls Ctrl-C, then calls the callback with `info` (built under the GIL). An exception in
  /// the callback stops the run and is raised once it has returned.
  void report(const std::function<py::dict()>& info) {
    poll();
    if (stop_ || callback_.is_none()) return;
    py::gil_scoped_acquire gil;
    try {
      const py::object answer = callback_(info());
      if (!answer.is_none() && !answer.cast<bool>()) {
        stop_ = true;
        cancelled_ = true;
      }
    } catch (py::error_already_set& e) {
      stop_ = true;
      error_ = std::make_unique<py::error_already_set>(std::move(e));
    }
  }
  /// After the run, with the GIL held: raises the callback's exception, if any.
  void raiseIfFailed() {
    if (error_) {
      py::error_already_set e = std::move(*error_);
      error_.reset();
      throw e;
    }
  }
  bool cancelled() const { return cancelled_; }

 private:
  std::atomic<bool> stop_{false};
  py::object callback_ = py::none();
  bool cancelled_ = false;
  std::unique_ptr<py::error_already_set> error_;
};

/// A per-joint option: None, one number for every joint, or n numbers.
std::optional<Eigen::VectorXd> jointOption(const py::handle& value, const char* name, int n) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value))
    return Eigen::VectorXd::Constant(n, value.cast<double>());
  return vectorArg(value, name, n);
}

SegmentOptions segmentOptions(double horizon, int segments, bool random_segments,
                              const std::string& integrator, double step, bool normalise,
                              std::uint64_t seed) {
  SegmentOptions s;
  s.horizon = horizon;
  s.num_segments = segments;
  s.random_starts = random_segments;
  s.integrator = parseIntegrator(integrator);
  s.step = step;
  s.normalise = normalise;
  s.seed = seed;
  return s;
}

/// The GC problem of a path or a Dataset.
Trajectory trajectoryOf(const DataArg& d, const Model& model) {
  return d.arrays ? *d.arrays : readDatasetCsv(d.path, model.numJoints());
}

// ---- simulate ----

Trajectory simulatePy(const Model& model, std::optional<double> duration, double dt, double rate,
                      const std::string& controller, const OptionalArrayLike& amplitude,
                      const OptionalArrayLike& q0, const OptionalArrayLike& frequency,
                      const OptionalArrayLike& phase, double base_frequency, int harmonics,
                      const OptionalArrayLike& kp, const OptionalArrayLike& kd,
                      const OptionalArrayLike& tau_max, double bandwidth,
                      const std::optional<Model>& controller_model, double controller_perturb,
                      const std::string& integrator, double noise_q, double noise_dq,
                      double noise_tau, std::uint64_t seed, const OptionalPathLike& trajectory) {
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
  py::gil_scoped_release release;
  return simulateRun(r).trajectory;
}

// ---- search ----

struct SearchPy {
  Model robot;
  SearchOutcome outcome;
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
  SearchPy out{robot, {}};
  {
    py::gil_scoped_release release;
    out.outcome = searchRun(r);
  }
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

// ---- refine ----

struct RefinePy {
  RefineOutcome outcome;
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
  {
    py::gil_scoped_release release;
    out.outcome = refineRun(r);
  }
  out.outcome.options.control = {};  // it points into `interrupt`, gone on return
  out.outcome.options.on_iteration = nullptr;
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

// ---- excite ----

struct ExcitePy {
  Model robot;
  ExcitationSettings settings;
  ExciteOutcome outcome;
};

ExcitePy excitePy(const Model& robot, const std::string& criterion, double period, int harmonics,
                  int starts, int evaluations, double budget_seconds, double grid_rate,
                  double check_rate, double torque_noise, int segments, double horizon,
                  const OptionalArrayLike& offset, const OptionalArrayLike& q_min,
                  const OptionalArrayLike& q_max, const OptionalArrayLike& dq_max,
                  const OptionalArrayLike& ddq_max, const OptionalArrayLike& tau_max,
                  double torque_margin, const std::optional<double>& floor, double base_radius,
                  int samples, std::uint64_t seed, double tolerance, int threads,
                  const PathLike& robot_spec_arg, const ProgressLike& progress) {
  const std::string robot_spec = pathArg(robot_spec_arg, "robot_spec");
  const int n = robot.numJoints();
  ExciteRequest r;  // checked by exciteRun
  r.robot = robot;
  r.criterion = parseExcitationCriterion(criterion);
  r.period = period;
  r.harmonics = harmonics;
  r.starts = starts;
  r.evaluations = evaluations;
  if (budget_seconds > 0.0) r.max_seconds = budget_seconds;
  r.grid_rate = grid_rate;
  r.check_rate = check_rate;
  r.torque_noise = torque_noise;
  r.gc_segments = segments;
  r.gc_horizon = horizon;
  r.seed = seed;
  r.threads = threads;
  r.structural = {samples, seed, tolerance};
  r.offset = jointOption(offset, "offset", n);
  LimitOverrides overrides;
  overrides.q_min = jointOption(q_min, "q_min", n);
  overrides.q_max = jointOption(q_max, "q_max", n);
  overrides.dq_max = jointOption(dq_max, "dq_max", n);
  overrides.ddq_max = jointOption(ddq_max, "ddq_max", n);
  overrides.tau_max = jointOption(tau_max, "tau_max", n);
  overrides.torque_margin = torque_margin;
  overrides.floor = floor;
  overrides.base_radius = base_radius;
  r.limits = excitationLimits(robot, overrides);
  if (r.offset) checkOffsets(robot, r.limits, *r.offset);
  Interrupt interrupt;
  interrupt.setCallback(progress);
  r.control.stop = interrupt.flag();
  r.control.progress = [&](const std::string& line) {  // after each start (any thread)
    interrupt.report([&] {
      py::dict d;
      d["line"] = line;
      return d;
    });
  };
  ExcitePy out{robot, {}, {}};
  out.settings.robot = robot_spec.empty() ? robot.name : robot_spec;
  out.settings.harmonics = harmonics;
  out.settings.evaluations = evaluations;
  out.settings.period = period;
  {
    py::gil_scoped_release release;
    out.outcome = exciteRun(r);
  }
  out.settings.starts = static_cast<int>(out.outcome.starts.size());  // 0 resolved
  interrupt.raiseIfFailed();
  if (!interrupt.cancelled()) interrupt.warnIfStopped();
  return out;
}

// ---- prepare ----

struct PreparePy {
  LogSource source;
  PrepareOptions options;
  PrepareOutcome outcome;
};

/// prepare()'s arrays as one file's RawSignals: t (N), q and tau (N x n; tau holds currents when
/// `current`), optional dq and ddq (N x n). ValueError for shapes that do not agree.
RawSignals arraySignals(const py::handle& t, const py::handle& q, const py::handle& tau,
                        const py::handle& dq, const py::handle& ddq, bool current) {
  if (t.is_none() || q.is_none() || tau.is_none())
    throw py::value_error("give tables (files), or arrays t, q and tau");
  const DoubleArray time = realArray(t, "t", {1});
  const auto samples = static_cast<Eigen::Index>(time.shape(0));
  RawSignals out;
  const auto matrix = [&](const py::handle& value, const char* name) {
    const DoubleArray a = realArray(value, name, {1, 2});
    const auto rows = static_cast<Eigen::Index>(a.shape(0));
    const Eigen::Index cols = a.ndim() == 2 ? static_cast<Eigen::Index>(a.shape(1)) : 1;
    if (rows != samples || (out.n > 0 && cols != out.n))
      throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(samples) +
                            ", " + std::to_string(out.n > 0 ? out.n : cols) + ") as t and q, not " +
                            shapeText(a));
    return RowMatrix(Eigen::Map<const RowMatrix>(a.data(), rows, cols));
  };
  const RowMatrix qm = matrix(q, "q");
  out.n = static_cast<int>(qm.cols());
  const RowMatrix taum = matrix(tau, current ? "tau (currents)" : "tau");
  out.has_dq = !dq.is_none();
  out.has_ddq = !ddq.is_none();
  out.values.resize(samples, 1 + (2 + (out.has_dq ? 1 : 0) + (out.has_ddq ? 1 : 0)) * out.n);
  // Times from the first stamp, in 64-bit precision (epoch seconds keep their digits).
  out.time_origin = samples > 0 ? static_cast<long double>(time.at(0)) : 0.0L;
  for (Eigen::Index k = 0; k < samples; ++k)
    out.values(k, 0) = static_cast<double>(static_cast<long double>(time.at(k)) - out.time_origin);
  out.values.middleCols(1, out.n) = qm;
  out.values.middleCols(1 + out.n, out.n) = taum;
  Eigen::Index at = 1 + 2 * out.n;
  if (out.has_dq) out.values.middleCols(at, out.n) = matrix(dq, "dq"), at += out.n;
  if (out.has_ddq) out.values.middleCols(at, out.n) = matrix(ddq, "ddq");
  out.rows = samples;
  out.ddq_at = 1 + (out.has_dq ? 3 : 2) * out.n;
  out.file = out.tau_file = "arrays";
  out.line_of = [](Eigen::Index k) { return static_cast<int>(k + 1); };  // the array's row
  return out;
}

/// prepare()'s cutoff (a frequency, 0, 'auto' or None) and tau_cutoff (a frequency, 'none' or
/// None) into the options.
void readCutoffs(const FrequencyLike& cutoff, const FrequencyLike& tau_cutoff, PrepareOptions& o) {
  if (py::isinstance<py::str>(cutoff)) {
    if (cutoff.cast<std::string>() != "auto")
      throw py::value_error("cutoff: expected a frequency [Hz], 0 (no filter), 'auto' or None");
    o.auto_cutoff = true;
  } else if (!cutoff.is_none()) {
    o.cutoff = cutoff.cast<double>();
    if (!(o.cutoff >= 0.0) || !std::isfinite(o.cutoff))
      throw py::value_error(
          "cutoff: expected a frequency >= 0 [Hz] (0: no filter), 'auto' or None");
  }
  if (py::isinstance<py::str>(tau_cutoff)) {
    if (tau_cutoff.cast<std::string>() != "none")
      throw py::value_error("tau_cutoff: expected a frequency [Hz], 'none' or None (q's)");
    o.tau_cutoff = 0.0;
  } else if (!tau_cutoff.is_none()) {
    o.tau_cutoff = tau_cutoff.cast<double>();
    if (!(o.tau_cutoff >= 0.0) || !std::isfinite(o.tau_cutoff))
      throw py::value_error("tau_cutoff: expected a frequency >= 0 [Hz], 'none' or None (q's)");
  }
}

PreparePy preparePy(
    const TablesLike& tables, const std::string& time_column, const std::string& q_columns,
    const std::string& dq_columns, const std::string& tau_columns, const std::string& ddq_columns,
    int joints, bool current, const OptionalArrayLike& torque_constants,
    const OptionalArrayLike& gear_ratios, const std::string& time_unit,
    const std::string& angle_unit, double rate, const FrequencyLike& cutoff, int order,
    int decimate, double max_gap, double trim, bool derive_dq, bool derive_ddq, bool savitzky_golay,
    int savgol_window, int savgol_degree, double validate_fraction, bool keep_stalled,
    const std::vector<std::pair<double, double>>& window,
    const std::vector<std::pair<long, long>>& rows, const OptionalArrayLike& dq_max,
    const OptionalArrayLike& ddq_max, const FrequencyLike& tau_cutoff, const std::string& topic,
    const std::string& stamp, const std::vector<std::string>& joint_names,
    const OptionalArrayLike& t, const OptionalArrayLike& q, const OptionalArrayLike& tau,
    const OptionalArrayLike& dq, const OptionalArrayLike& ddq, const std::string& effort_topic,
    const OptionalPathLike& effort_log, bool keep_raw_torque, int threads, bool skip_missing,
    const std::string& joint_prefix, bool decimal_comma) {
  PreparePy out;
  LogSource& s = out.source;
  s.skip_missing = skip_missing;
  s.decimal_comma = decimal_comma;
  if (tables.is_none()) {
    s.arrays = std::make_shared<const RawSignals>(arraySignals(t, q, tau, dq, ddq, current));
  } else if (!t.is_none() || !q.is_none() || !tau.is_none() || !dq.is_none() || !ddq.is_none()) {
    throw py::value_error("give tables (files) or arrays (t, q, tau, ...), not both");
  } else if (py::isinstance<py::list>(tables) || py::isinstance<py::tuple>(tables)) {
    for (const py::handle& t : tables) s.tables.push_back(pathArg(t, "tables"));
  } else {
    s.tables.push_back(pathArg(tables, "tables"));
  }
  if (s.tables.empty() && s.arrays == nullptr)
    throw py::value_error("tables: expected at least one log file");
  const bool recordings = std::any_of(s.tables.begin(), s.tables.end(),
                                      [](const std::string& t) { return bags::isBag(t); });
  if (!recordings && (!topic.empty() || stamp != "header" || !effort_topic.empty() ||
                      !joint_prefix.empty() || !joint_names.empty()))
    throw py::value_error(
        "topic, stamp, effort_topic, joint_prefix and joint_names apply to recordings (.mcap, "
        ".db3, .bag, bag directories), not to tables or arrays");
  s.effort_topic = effort_topic;
  if (!effort_log.is_none()) s.effort_table = pathArg(effort_log, "effort_log");
  s.time_column = time_column;
  s.q_columns = q_columns;
  s.dq_columns = dq_columns;
  s.tau_columns = tau_columns;
  s.ddq_columns = ddq_columns;
  s.num_joints = joints;
  s.current = current;
  s.topic = topic;
  if (stamp != "header" && stamp != "receive")
    throw py::value_error("stamp: expected 'header' or 'receive', not '" + stamp + "'");
  s.receive_time = stamp == "receive";
  s.joint_names = joint_names;
  s.joint_prefix = joint_prefix;
  PrepareOptions& o = out.options;
  o.time_scale = timeUnitScale(time_unit);
  o.angle_scale = angleUnitScale(angle_unit);
  o.rate = rate;
  readCutoffs(cutoff, tau_cutoff, o);
  o.order = order;
  o.decimate = decimate;
  o.max_gap = max_gap;
  o.trim = trim;  // < 0: 2 / cutoff (PrepareOptions::check refuses below -1)
  o.derive_dq = derive_dq;
  o.derive_ddq = derive_ddq;
  o.savitzky_golay = savitzky_golay;
  o.savgol_window = savgol_window;
  o.savgol_degree = savgol_degree;
  if (!savitzky_golay && (savgol_window != PrepareOptions{}.savgol_window ||
                          savgol_degree != PrepareOptions{}.savgol_degree))
    throw py::value_error("savgol_window and savgol_degree apply to savitzky_golay=True");
  o.validate_fraction = validate_fraction;
  o.keep_stalled = keep_stalled;
  o.keep_raw_torque = keep_raw_torque;
  o.windows = window;
  o.row_windows = rows;
  for (const auto& [given, target, name] :
       {std::tuple{&dq_max, &o.dq_bound, "dq_max"}, std::tuple{&ddq_max, &o.ddq_bound, "ddq_max"}})
    if (!given->is_none()) {
      const DoubleArray b = realArray(*given, name, {0, 1});
      *target = Eigen::Map<const Eigen::VectorXd>(b.data(), b.size());
    }
  if (!torque_constants.is_none()) {
    const DoubleArray k = realArray(torque_constants, "torque_constants", {1});
    o.torque_constants = Eigen::Map<const Eigen::VectorXd>(k.data(), k.shape(0));
  }
  if (!gear_ratios.is_none()) {
    const DoubleArray g = realArray(gear_ratios, "gear_ratios", {1});
    o.gear_ratios = Eigen::Map<const Eigen::VectorXd>(g.data(), g.shape(0));
  }
  py::gil_scoped_release release;
  out.outcome = prepareLog(out.source, out.options, threads);
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
      "`dynid simulate`: the robot under a tracking controller, returned as a Dataset. "
      "Per-joint settings take one number or n; trajectory: an excitation.json design, one period "
      "unless duration is given (default duration: 10 s).");

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
          "to_json", [](const SearchPy& s) { return jsonText(searchJson(s.outcome), 1) + "\n"; },
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
          "to_json", [](const RefinePy& r) { return jsonText(refineJson(r.outcome), 1) + "\n"; },
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

void bindExcite(py::module_& m) {
  py::class_<ExcitePy>(m, "Excitation", "What `dynid excite` writes as excitation.json.")
      .def_property_readonly(
          "period", [](const ExcitePy& e) { return e.outcome.design.period; },
          "The motion's period [s].")
      .def_property_readonly(
          "offset", [](const ExcitePy& e) { return toNumpy(e.outcome.design.offset); },
          "Each joint's centre of motion, shape (n,) [rad].")
      .def_property_readonly(
          "a", [](const ExcitePy& e) { return toNumpy(e.outcome.design.a); },
          "The Fourier coefficients a_jk of the sine terms (q_j = offset_j + sum_k a_jk/(w k) "
          "sin(w k t) - b_jk/(w k) cos(w k t)), shape (n, harmonics) [rad/s].")
      .def_property_readonly(
          "b", [](const ExcitePy& e) { return toNumpy(e.outcome.design.b); },
          "The Fourier coefficients b_jk of the cosine terms, shape (n, harmonics) [rad/s].")
      .def_property_readonly(
          "condition_number", [](const ExcitePy& e) { return e.outcome.score.condition_unit; },
          "The designed motion's base regressor condition number (unit columns).")
      .def_property_readonly(
          "baseline_condition_number",
          [](const ExcitePy& e) { return e.outcome.baseline.condition_unit; },
          "The default sinusoid's, for comparison.")
      .def_property_readonly(
          "termination", [](const ExcitePy& e) { return e.outcome.termination; },
          "Why the design stopped (evaluations, seconds, tolerance or interrupted).")
      .def(
          "sample",
          [](const ExcitePy& e, double rate) {
            py::gil_scoped_release release;
            return sampleFourier(e.outcome.design, e.robot, rate);
          },
          py::arg("rate") = ExcitationSettings{}.csv_rate,
          "One period of the motion at `rate` as a Dataset (tau: the model's inverse dynamics).")
      .def(
          "to_json",
          [](const ExcitePy& e) {
            return jsonText(excitationJson(e.robot, e.settings, e.outcome), 2) + "\n";
          },
          "excitation.json, as `dynid excite` writes it (simulate(trajectory=...) reads it).");

  m.def(
      "excite", &excitePy, py::arg("robot"), py::arg("criterion") = "cond",
      py::arg("period") = ExciteRequest{}.period, py::arg("harmonics") = ExciteRequest{}.harmonics,
      py::arg("starts") = ExciteRequest{}.starts,
      py::arg("evaluations") = ExciteRequest{}.evaluations, py::arg("budget_seconds") = 0.0,
      py::arg("grid_rate") = ExciteRequest{}.grid_rate,
      py::arg("check_rate") = ExciteRequest{}.check_rate,
      py::arg("torque_noise") = ExciteRequest{}.torque_noise,
      py::arg("segments") = ExciteRequest{}.gc_segments,
      py::arg("horizon") = ExciteRequest{}.gc_horizon, py::arg("offset") = py::none(),
      py::arg("q_min") = py::none(), py::arg("q_max") = py::none(), py::arg("dq_max") = py::none(),
      py::arg("ddq_max") = py::none(), py::arg("tau_max") = py::none(),
      py::arg("torque_margin") = LimitOverrides{}.torque_margin, py::arg("floor") = py::none(),
      py::arg("base_radius") = LimitOverrides{}.base_radius,
      py::arg("samples") = StructuralOptions{}.samples, py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
      py::arg("robot_spec") = "", py::arg("progress") = py::none(),
      "`dynid excite`: a periodic Fourier motion within the limits that excites the base "
      "parameters (criterion 'cond', 'cond-unscaled', 'd-optimal', 'gc' or 'relative-sd'). "
      "progress(info) is called as each start ends with a dict whose 'line' is the CLI's (the "
      "start, its criterion, the share done and the time left); returning False stops the "
      "design with the best start so far.");
}

void bindPrepare(py::module_& m) {
  py::class_<PreparePy>(m, "Preparation",
                        "What `dynid prepare` writes (train, validate, "
                        "prepare.json).")
      .def_property_readonly(
          "train", [](const PreparePy& p) { return p.outcome.train; },
          "The training Dataset (train.csv).")
      .def_property_readonly(
          "validate",
          [](const PreparePy& p) -> std::optional<Trajectory> {
            if (p.outcome.validate.numSamples() == 0) return std::nullopt;
            return p.outcome.validate;
          },
          "The held-out Dataset (validate.csv), or None when nothing was held out.")
      .def_property_readonly(
          "rate", [](const PreparePy& p) { return p.outcome.rate; }, "The output rate [Hz].")
      .def_property_readonly(
          "cutoff", [](const PreparePy& p) { return p.outcome.cutoff; },
          "The low-pass cutoff applied to q, dq (and tau unless tau_cutoff differs) [Hz]; 0 for "
          "none.")
      .def_property_readonly(
          "tau_noise", [](const PreparePy& p) { return toNumpy(p.outcome.tau_noise); },
          "Each joint's torque noise estimate, the RMS of the resampled minus the filtered torque, "
          "shape (n,) [N m].")
      .def_property_readonly(
          "warnings", [](const PreparePy& p) { return p.outcome.warnings; },
          "What prepare warns about (rest at the ends, a cutoff near the trajectory band, ...).")
      .def_property_readonly(
          "raw_validate_time",
          [](const PreparePy& p) { return toNumpy(p.outcome.raw_validate_time); },
          "With keep_raw_torque, the held-out raw torques' stamps (N,) [s].")
      .def_property_readonly(
          "raw_validate_tau",
          [](const PreparePy& p) { return toNumpy(p.outcome.raw_validate_tau); },
          "With keep_raw_torque, the held-out raw torques as logged, shape (N, n) [N m].")
      .def_property_readonly(
          "time_origin",
          [](const PreparePy& p) { return static_cast<double>(p.outcome.time_origin); },
          "the log's first stamp [s]: every time is the stamp minus it")
      .def(
          "to_json",
          [](const PreparePy& p) {
            return jsonText(prepareJson(p.source, p.options, p.outcome), 2) + "\n";
          },
          "prepare.json, as `dynid prepare` writes it.");

  m.def(
      "prepare", &preparePy, py::arg("tables") = py::none(), py::arg("time_column") = "1",
      py::arg("q_columns") = "", py::arg("dq_columns") = "", py::arg("tau_columns") = "",
      py::arg("ddq_columns") = "", py::arg("joints") = LogSource{}.num_joints,
      py::arg("current") = false, py::arg("torque_constants") = py::none(),
      py::arg("gear_ratios") = py::none(), py::arg("time_unit") = "s",
      py::arg("angle_unit") = "rad", py::arg("rate") = PrepareOptions{}.rate,
      py::arg("cutoff") = py::none(), py::arg("order") = PrepareOptions{}.order,
      py::arg("decimate") = PrepareOptions{}.decimate,
      py::arg("max_gap") = PrepareOptions{}.max_gap, py::arg("trim") = PrepareOptions{}.trim,
      py::arg("derive_dq") = false, py::arg("derive_ddq") = false,
      py::arg("savitzky_golay") = false, py::arg("savgol_window") = PrepareOptions{}.savgol_window,
      py::arg("savgol_degree") = PrepareOptions{}.savgol_degree,
      py::arg("validate_fraction") = PrepareOptions{}.validate_fraction,
      py::arg("keep_stalled") = false, py::arg("window") = std::vector<std::pair<double, double>>{},
      py::arg("rows") = std::vector<std::pair<long, long>>{}, py::arg("dq_max") = py::none(),
      py::arg("ddq_max") = py::none(), py::arg("tau_cutoff") = py::none(),
      py::arg("topic") = LogSource{}.topic, py::arg("stamp") = "header",
      py::arg("joint_names") = std::vector<std::string>{}, py::arg("t") = py::none(),
      py::arg("q") = py::none(), py::arg("tau") = py::none(), py::arg("dq") = py::none(),
      py::arg("ddq") = py::none(), py::arg("effort_topic") = LogSource{}.effort_topic,
      py::arg("effort_log") = py::none(), py::arg("keep_raw_torque") = false,
      py::arg("threads") = kAllThreads, py::arg("skip_missing") = false,
      py::arg("joint_prefix") = "", py::arg("decimal_comma") = false,
      "`dynid prepare`: a raw log (one table or a list; column selectors as the CLI's) "
      "resampled, filtered and differentiated into Datasets. cutoff: None for the default, 0 "
      "for no filter, a frequency [Hz] or 'auto'. window: [(from, to), ...] seconds from the "
      "log's first stamp; rows: [(first, last), ...] 1-based data rows; dq_max, ddq_max: "
      "plausibility bounds (one, or one per joint); tau_cutoff: torque's own low-pass [Hz], "
      "'none', or None for the cutoff's. Recordings (.mcap, .db3, .bag, rosbag2 bag "
      "directories): topic (the JointState topic; default the only one), stamp ('header' or "
      "'receive'), joint_names (the robot's joints in order, matched by name: "
      "Model.joint_names; default the first message's), effort_topic or effort_log (a second "
      "JointState topic, or a table with time_column and tau_columns, giving the torques when "
      "the messages carry none). Arrays instead of files: tables=None and t (N,), q and tau "
      "(N, n; currents with current=True), optionally dq and ddq (N, n), in the units "
      "time_unit and angle_unit name. keep_raw_torque: also keep the held-out raw torques at "
      "the log's stamps (raw_validate_time, raw_validate_tau: the CLI's validate_raw.csv). "
      "threads: the joints are prepared on them (0: every core; the same numbers for any "
      "count). skip_missing: leave out table rows whose selected field is empty, nan or inf, "
      "as prepare --skip-missing. joint_prefix: recordings name joint_names with this prefix "
      "(--joint-prefix). decimal_comma: tables write ',' for the decimal point "
      "(--decimal-comma).");
}

}  // namespace

void bindSearch(py::module_& m) {
  bindSimulate(m);
  bindSearchRuns(m);
  bindRefine(m);
  bindExcite(m);
  bindPrepare(m);
}

}  // namespace dynid::python
