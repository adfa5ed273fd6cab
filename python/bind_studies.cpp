// The studies wing: dynid audit (analysis/studies/audit.hpp), its document as a dict; the pieces
// of a batch grid (analysis/studies/batch.hpp) that dynid.batch runs on a Dask cluster
// (dynid_distributed.batch): the plan, one run, a run's record stored, the tables.
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/records/document.hpp"
#include "analysis/studies/audit.hpp"
#include "analysis/studies/batch.hpp"
#include "core/errors.hpp"
#include "python/run_support.hpp"
#include "reports/audit_report.hpp"
#include "reports/batch_report.hpp"
#include "reports/output.hpp"

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

/// The runs of the manifest's grid still to do in `out`: [(name, spec as JSON text)], after
/// planBatch's checks (every run valid before any starts).
std::vector<std::pair<std::string, std::string>> batchPlan(const PathLike& manifest,
                                                           const PathLike& out, bool quick) {
  const BatchPlan plan = planBatch(pathArg(manifest, "manifest"), pathArg(out, "out"), quick, 1, 1);
  std::vector<std::pair<std::string, std::string>> todo;
  for (std::size_t i : plan.todo)
    todo.emplace_back(batchRunName(i, plan.runs[i]), plan.runs[i].dump());
  return todo;
}

/// One run of a spec (JSON text): its record's document (what out/runs/<name>.json holds).
std::string batchRun(const std::string& spec) {
  const nlohmann::json parsed = parseJson(spec, "spec");
  py::gil_scoped_release release;
  return batchRunDocument(runBatchSpec(parsed));
}

/// A run's record stored as out/runs/<name>.json (atomically; earlier runs stay).
void batchStore(const PathLike& out, const std::string& name, const std::string& record) {
  if (name.empty() || name.find('/') != std::string::npos || name[0] == '.')
    throw InputError("run name '" + name + "': not a plain file name");
  OutputSet runs(pathArg(out, "out") + "/runs", false);
  runs.add(name + ".json", record);
  runs.publish();
}

/// The grid's stored runs collected, results.csv and results.json written: results.json as a dict.
py::dict batchFinish(const PathLike& manifest, const PathLike& out, bool quick) {
  const std::string dir = pathArg(out, "out");
  const BatchOutcome outcome =
      collectBatch(planBatch(pathArg(manifest, "manifest"), dir, quick, 1, 1));
  writeBatchTables(dir, outcome);
  return parsedJson(nlohmann::json::parse(batchResultsJson(outcome))).cast<py::dict>();
}

void bindBatch(py::module_& m) {
  m.def("_batch_plan", &batchPlan, py::arg("manifest"), py::arg("out"), py::arg("quick") = false,
        "dynid.batch's plan: [(name, spec JSON)] of the grid's runs not yet stored in `out`.");
  m.def("_batch_run", &batchRun, py::arg("spec"),
        "dynid.batch's task: one run of a spec (JSON), its record as JSON text.");
  m.def("_batch_store", &batchStore, py::arg("out"), py::arg("name"), py::arg("record"),
        "dynid.batch: a run's record stored as out/runs/<name>.json.");
  m.def("_batch_finish", &batchFinish, py::arg("manifest"), py::arg("out"),
        py::arg("quick") = false,
        "dynid.batch: the stored runs collected into results.csv and results.json (returned).");
  m.def(
      "batch",
      [](const py::args& args, const py::kwargs& kwargs) {
        return callDistributed("batch", args, kwargs);
      },
      "`dynid batch` on a Dask cluster. Arguments: manifest, out, client=None (a "
      "distributed.Client; None: a local cluster of one worker per core), quick=False, "
      "retries=2. Every run of the manifest's grid not yet stored in `out` is a task; each "
      "record is stored in out/runs as it comes back (a batch stopped resumes), then "
      "results.csv and results.json are written. Returns results.json as a dict, with "
      "\"failed\": {run: error}.");
}

}  // namespace

void bindStudies(py::module_& m) {
  bindAudit(m);
  bindBatch(m);
}

}  // namespace dynid::python
