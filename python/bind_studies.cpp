// The studies wing: dynid audit (analysis/studies/audit.hpp), its document as a dict.
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/studies/audit.hpp"
#include "core/errors.hpp"
#include "python/run_support.hpp"
#include "reports/audit_report.hpp"

namespace dynid::python {
namespace {

py::dict audit(const PathsLike& estimates, const PathsLike& data, const PathLike& robot,
               const TermsLike& drive_terms, const std::string& method, double level, int threads) {
  checkThreads(threads);
  AuditRequest request;
  if (!estimates.is_none())
    for (const py::handle& e : estimates) request.estimate_files.push_back(pathArg(e, "estimates"));
  if (!data.is_none())
    for (const py::handle& d : data) request.data_files.push_back(pathArg(d, "data"));
  request.robot = pathArg(robot, "robot");
  if (!drive_terms.is_none() &&
      !(py::isinstance<py::str>(drive_terms) && drive_terms.cast<std::string>().empty()))
    request.drive_terms = driveTermsArg(drive_terms, "drive_terms");
  request.method = parseMethod(method, {Method::kOls, Method::kWls, Method::kPc});
  request.level = level;
  request.threads = threads;
  AuditOutcome out;
  {
    py::gil_scoped_release release;
    out = auditRun(request);
  }
  return parsedJson(auditJson(out));
}

void bindAudit(py::module_& m) {
  m.def("audit", &audit, py::arg("estimates") = py::none(), py::arg("data") = py::none(),
        py::arg("robot") = "", py::arg("drive_terms") = "", py::arg("method") = "ols",
        py::arg("level") = kDefaultAuditLevel, py::arg("threads") = kAllThreads,
        "`dynid audit`: estimate.json paths, or log paths identified with `robot`, "
        "`drive_terms` and `method`. Returns audit.json as a dict (per-parameter tests, verdict).");
}

}  // namespace

void bindStudies(py::module_& m) { bindAudit(m); }

}  // namespace dynid::python
