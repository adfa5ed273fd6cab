// The monitor wing: dynid monitor on a log file (analysis/monitor/monitor.hpp), its document as a
// dict.
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/monitor/monitor.hpp"
#include "core/errors.hpp"
#include "python/run_support.hpp"
#include "reports/monitor_report.hpp"

namespace dynid::python {
namespace {

py::dict monitor(const PathLike& arm_arg, const PathLike& data, const OptionalPathLike& calibration,
                 const OptionalPathLike& thresholds, const std::string& residual,
                 const OptionalArrayLike& gain, double false_alarms_per_hour, double hold,
                 double max_gap, const OptionalPathLike& truth, const PathLike& robot_spec,
                 int threads, const std::string& topic, const std::string& stamp,
                 const std::string& effort_topic, const OptionalArrayLike& torque_constants,
                 const OptionalArrayLike& gear_ratios, const std::string& joint_prefix,
                 const std::vector<std::string>& joint_names) {
  checkThreads(threads);
  MonitorRequest request;
  request.arm = pathArg(arm_arg, "arm");
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  request.data_file = pathArg(data, "data");
  if (request.data_file == "-") throw py::value_error("data: a file (stdin is the CLI's)");
  if (!calibration.is_none()) request.calibration_file = pathArg(calibration, "calibration");
  if (!thresholds.is_none()) request.thresholds_file = pathArg(thresholds, "thresholds");
  if (!truth.is_none()) request.truth_file = pathArg(truth, "truth");
  if (residual != "observer" && residual != "direct")
    throw py::value_error("residual must be 'observer' or 'direct', not '" + residual + "'");
  request.residual = residual == "direct" ? MonitorResidual::kDirect : MonitorResidual::kObserver;
  if (!gain.is_none()) {
    if (py::isinstance<py::float_>(gain) || py::isinstance<py::int_>(gain))
      request.gain = Eigen::VectorXd::Constant(1, gain.cast<double>());
    else
      request.gain = gain.cast<Eigen::VectorXd>();
  }
  if (stamp != "header" && stamp != "receive")
    throw py::value_error("stamp: expected 'header' or 'receive', not '" + stamp + "'");
  request.topic = topic;
  request.effort_topic = effort_topic;
  request.joint_prefix = joint_prefix;
  request.joint_names = joint_names;
  request.receive_time = stamp == "receive";
  for (const auto& [given, target, name] :
       {std::tuple{&torque_constants, &request.torque_constants, "torque_constants"},
        std::tuple{&gear_ratios, &request.gear_ratios, "gear_ratios"}})
    if (!given->is_none()) {
      const DoubleArray values = realArray(*given, name, {1});
      *target = Eigen::Map<const Eigen::VectorXd>(values.data(), values.shape(0));
    }
  request.false_alarms_per_hour = false_alarms_per_hour;
  request.hold = hold;
  request.max_gap = max_gap;
  request.threads = threads;
  MonitorOutcome out;
  {
    py::gil_scoped_release release;
    out = monitorRun(request);
  }
  pythonTexts(out.warnings);  // the fields they name, as keyword arguments
  return parsedJson(monitorJson(out));
}

void bindMonitorRun(py::module_& m) {
  m.def("monitor", &monitor, py::arg("arm"), py::arg("data"), py::arg("calibration") = py::none(),
        py::arg("thresholds") = py::none(), py::arg("residual") = "observer",
        py::arg("gain") = py::none(), py::arg("false_alarms_per_hour") = kDefaultFalseAlarmsPerHour,
        py::arg("hold") = kDefaultEventHold, py::arg("max_gap") = kDefaultMaxGap,
        py::arg("truth") = py::none(), py::arg("robot_spec") = "", py::arg("threads") = kAllThreads,
        py::arg("topic") = "", py::arg("stamp") = "header", py::arg("effort_topic") = "",
        py::arg("torque_constants") = py::none(), py::arg("gear_ratios") = py::none(),
        py::arg("joint_prefix") = "", py::arg("joint_names") = std::vector<std::string>{},
        "`dynid monitor` on a log file (a dataset CSV, or a recording: .mcap, .db3, .bag or a "
        "bag directory, with its JointState `topic`, `stamp` 'header' or 'receive', and "
        "`effort_topic`; a recording's efforts that are motor currents become torques through "
        "`torque_constants` [N m/A] and `gear_ratios`, per joint; `joint_prefix` and "
        "`joint_names` as --joint-prefix and --joint-names): `arm` an estimate.json, "
        "URDF, dynid model or robot spec; "
        "thresholds from a clean `calibration` log or a saved `thresholds` file (one of them). "
        "Returns monitor.json as a dict (events, thresholds, statistics, truth scores).");
}

}  // namespace

void bindMonitor(py::module_& m) { bindMonitorRun(m); }

}  // namespace dynid::python
