// The fleet wing (analysis/fleet/fleet.hpp): fleet(), its document as a dict. With a Dask client,
// the robots' logs are summarized on the cluster first (dynid_distributed.fleet), then the fleet is
// learnt here from their summaries.
#include <pybind11/stl.h>

#include "analysis/fleet/fleet.hpp"
#include "core/errors.hpp"
#include "python/run_support.hpp"
#include "python/summary_result.hpp"
#include "reports/fleet_report.hpp"

namespace dynid::python {
namespace {

/// One robot of `robots`: a Summary, a log path, or a list of log paths.
FleetRobotInput robotArg(const std::string& name, const py::handle& value,
                         std::vector<std::string>& files) {
  FleetRobotInput robot;
  robot.name = name;
  if (py::isinstance<SummaryResult>(value)) {
    robot.summary = &value.cast<const SummaryResult&>().summary;
    return robot;
  }
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    robot.data_files.push_back(pathArg(value, "robots"));
  } else if (py::isinstance<py::sequence>(value)) {
    for (const py::handle& log : value) robot.data_files.push_back(pathArg(log, "robots"));
  } else {
    throw py::type_error("robots['" + name +
                         "']: expected a Summary, a log path or a list of log paths");
  }
  files.insert(files.end(), robot.data_files.begin(), robot.data_files.end());
  return robot;
}

py::dict fleet(const Model& model, const FleetRobotsLike& robots, const std::string& method,
               const std::string& covariance, double flag_level,
               const std::optional<std::vector<double>>& rest_velocity,
               const TorqueFilterLike& torque_filter, int threads, const PathLike& robot_spec,
               const ClientLike& client, const ProgressLike& progress) {
  if (!py::isinstance<py::dict>(robots))
    throw py::type_error("robots: expected a dict {name: a Summary, a log path or a list of them}");
  if (!client.is_none()) {
    py::kwargs kwargs;
    kwargs["client"] = client;
    kwargs["method"] = method;
    kwargs["covariance"] = covariance;
    kwargs["flag_level"] = flag_level;
    kwargs["rest_velocity"] = rest_velocity;
    kwargs["torque_filter"] = torque_filter;
    kwargs["robot_spec"] = robot_spec;
    return callDistributed("fleet", py::make_tuple(model, robots), kwargs).cast<py::dict>();
  }
  checkThreads(threads);
  FleetRequest request;
  request.model = model;
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  std::vector<std::string> files;
  for (const auto& [name, value] : robots.cast<py::dict>())
    request.robots.push_back(robotArg(py::str(name).cast<std::string>(), value, files));
  request.method = parseMethod(method, {Method::kOls, Method::kWls});
  request.covariance = covariancePolicyFrom(covariance);
  request.prior.flag_level = flag_level;
  if (rest_velocity) request.rest_velocity = *rest_velocity;
  request.torque_filter = torqueFilterArg(torque_filter);
  request.threads = threads;
  Interrupt interrupt;
  interrupt.connect(request.control, progress);
  const PythonRun call("fleet", files, std::nullopt, threads);
  FleetOutcome out;
  {
    py::gil_scoped_release release;  // the robots' Summaries are kept alive by `robots`
    out = fleetRun(request);
  }
  interrupt.raiseIfFailed();
  interrupt.warnIfStopped();
  if (out.robots.empty())
    throw InputError("interrupted before three robots were estimated: no fleet");
  warnAll(out.warnings);
  return parsedJson(withCall(fleetJson(out), call.finish())).cast<py::dict>();
}

}  // namespace

void bindFleet(py::module_& m) {
  m.def("fleet", &fleet, py::arg("model"), py::arg("robots"), py::arg("method") = "ols",
        py::arg("covariance") = "hac", py::arg("flag_level") = FleetOptions{}.flag_level,
        py::arg("rest_velocity") = py::none(), py::arg("torque_filter") = "auto",
        py::arg("threads") = kAllThreads, py::arg("robot_spec") = "",
        py::arg("client") = py::none(), py::arg("progress") = py::none(),
        "`dynid fleet`: robots of one model at once. `robots`: {name: a Summary, a log path or a "
        "list of log paths}. Each robot's own estimate (`method` ols or wls), the fleet's prior "
        "learnt from them (empirical Bayes: per base parameter the fleet's mean and spread), the "
        "robots and parameters outside the fleet and each robot's posterior. With `client` (a "
        "distributed.Client) the logs are summarized on the Dask cluster first. Returns "
        "fleet.json as a dict.");
}

}  // namespace dynid::python
