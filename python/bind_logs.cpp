// The logs wing: dynid prepare (analysis/logs/prepare.hpp) on tables, per-signal files, recordings
// or arrays, its preparation as to_json().
#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/logs/prepare.hpp"
#include "analysis/logs/read_log.hpp"
#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/bags/bag.hpp"
#include "python/run_support.hpp"
#include "reports/prepare_report.hpp"

namespace dynid::python {
namespace {

// ---- prepare ----

struct PreparePy {
  LogSource source;
  PrepareOptions options;
  PrepareOutcome outcome;
  RunProvenance provenance;  // the call that made it
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

/// prepare()'s plausibility bounds and current-to-torque scales.
void readBoundsAndScales(const OptionalArrayLike& dq_max, const OptionalArrayLike& ddq_max,
                         const OptionalArrayLike& torque_constants,
                         const OptionalArrayLike& gear_ratios, PrepareOptions& o) {
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
}

/// prepare()'s log: its files (`tables`) or arrays (t, q, tau and optionally dq, ddq), not both.
void readTablesOrArrays(const TablesLike& tables, const OptionalArrayLike& t,
                        const OptionalArrayLike& q, const OptionalArrayLike& tau,
                        const OptionalArrayLike& dq, const OptionalArrayLike& ddq, bool current,
                        LogSource& s) {
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
  readTablesOrArrays(tables, t, q, tau, dq, ddq, current, s);
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
  readBoundsAndScales(dq_max, ddq_max, torque_constants, gear_ratios, o);
  std::vector<std::string> files = s.tables;
  files.push_back(s.effort_table);
  const PythonRun call("prepare", files, std::nullopt, threads);
  py::gil_scoped_release release;
  out.outcome = prepareLog(out.source, out.options, threads);
  out.provenance = call.finish();
  pythonTexts(out.outcome.warnings);  // the fields they name, as keyword arguments
  out.outcome.cutoff_reason = pythonText(out.outcome.cutoff_reason);
  return out;
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
            return jsonText(withCall(prepareJson(p.source, p.options, p.outcome), p.provenance),
                            2) +
                   "\n";
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

void bindLogs(py::module_& m) { bindPrepare(m); }

}  // namespace dynid::python
