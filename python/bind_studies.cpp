// The studies wing: dynid audit (analysis/studies/audit.hpp) and dynid study
// (analysis/studies/log_study.hpp), their documents as dicts; the pieces of a batch grid
// (analysis/studies/batch.hpp) that dynid.batch runs on a Dask cluster (dynid_distributed.batch):
// the plan, one run, a run's record stored, the tables.
#include <cmath>
#include <cstdint>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/estimation/front.hpp"
#include "analysis/records/document.hpp"
#include "analysis/studies/audit.hpp"
#include "analysis/studies/batch.hpp"
#include "analysis/studies/log_study.hpp"
#include "core/errors.hpp"
#include "python/run_support.hpp"
#include "reports/audit_report.hpp"
#include "reports/batch_report.hpp"
#include "reports/log_study_report.hpp"
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

py::dict study(const Model& model, const PathLike& data, const PathLike& validate,
               const std::string& methods, bool front,
               const std::optional<std::vector<double>>& front_weights, double front_tolerance,
               double search_seconds, long search_evaluations, int refine_iterations,
               double refine_seconds, int segments, std::uint64_t seed, int threads,
               const PathLike& robot_spec, const ProgressLike& progress) {
  checkThreads(threads);
  LogStudyRequest request;
  request.robot = model;
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  request.data_file = pathArg(data, "data");
  request.validate_file = pathArg(validate, "validate");
  request.methods = parseMethods(methods);
  if (front_weights)
    request.front_weights = *front_weights;
  else if (front)
    request.front_weights = defaultFrontWeights();
  request.front_tolerance = front_tolerance;
  request.search_seconds = search_seconds;
  request.search_evaluations = search_evaluations;
  request.refine_iterations = refine_iterations;
  request.refine_seconds = refine_seconds;
  request.segments.num_segments = segments;
  request.seed = request.segments.seed = seed;
  request.threads = threads;
  Interrupt interrupt;
  interrupt.connect(request.control, progress);
  const PythonRun call("study", {request.data_file, request.validate_file}, seed, threads);
  LogStudyOutcome out;
  {
    py::gil_scoped_release release;
    out = logStudyRun(request);
  }
  interrupt.raiseIfFailed();
  interrupt.warnIfStopped();
  return parsedJson(withCall(logStudyJson(out), call.finish())).cast<py::dict>();
}

void bindStudy(py::module_& m) {
  const LogStudyRequest d;
  m.def("study", &study, py::arg("model"), py::arg("data"), py::arg("validate"),
        py::arg("methods") = "all", py::arg("front") = false, py::arg("front_weights") = py::none(),
        py::arg("front_tolerance") = d.front_tolerance,
        py::arg("search_seconds") = d.search_seconds,
        py::arg("search_evaluations") = d.search_evaluations,
        py::arg("refine_iterations") = d.refine_iterations,
        py::arg("refine_seconds") = d.refine_seconds, py::arg("segments") = d.segments.num_segments,
        py::arg("seed") = d.seed, py::arg("threads") = kAllThreads, py::arg("robot_spec") = "",
        py::arg("progress") = py::none(),
        "`dynid study`: every method (`methods`, comma-separated, or all) on a training and a "
        "held-out dataset, torque fit and motion prediction side by side; with `front` (or "
        "`front_weights`) the combined estimator's front, and the estimate chosen from every "
        "consistent one (`front_tolerance`). Returns study.json as a dict: `methods`, "
        "`front.points` (each point's weight, errors and `standard` parameters) and `choice`.");
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
  bindStudy(m);
  bindBatch(m);
}

}  // namespace dynid::python
