// The runs wing's summarize room (analysis/runs/summarize.hpp): summarize() and the Summary it
// returns (mergeable with +, picklable through its summary.json, what identify() takes as data).
#include <algorithm>
#include <cstdint>
#include <cstring>

#include <pybind11/stl.h>

#include "analysis/records/document.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "python/run_support.hpp"
#include "python/summary_result.hpp"
#include "reports/summary_report.hpp"

namespace dynid::python {
namespace {

SummaryResult summarize(const Model& model, const DataLike& data,
                        const std::optional<std::vector<double>>& rest_velocity,
                        const TorqueFilterLike& torque_filter, int samples, std::uint64_t seed,
                        double tolerance, int threads, const PathLike& robot_spec) {
  SummarizeRequest request;  // checked by summarizeRun
  request.model = model;
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  request.structural = StructuralOptions{samples, seed, tolerance};
  request.threads = threads;
  if (rest_velocity) request.rest_velocity = *rest_velocity;
  request.torque_filter = torqueFilterArg(torque_filter);
  const DataArg arg = dataArg(data, "data", model);
  if (arg.arrays) {
    request.data = arg.arrays;
    request.data_name = arg.path;
  } else {
    request.data_files = {arg.path};
  }
  const PythonRun call("summarize", {arg.arrays ? std::string() : arg.path}, seed, threads);
  SummarizeOutcome outcome;
  {
    py::gil_scoped_release release;  // the Dataset is kept alive by the caller's reference
    outcome = summarizeRun(request);
  }
  return {std::move(outcome.summaries.front()), call.finish()};
}

/// The summary's name in a merge's messages: its logs.
std::string nameOf(const Summary& s) {
  if (s.sources.empty()) return "a summary";
  const std::string first = s.sources.front().file.empty() ? "<arrays>" : s.sources.front().file;
  return "the summary of " + first + (s.sources.size() > 1 ? " and more" : "");
}

SummaryResult merged(const SummaryResult& a, const SummaryResult& b) {
  const std::vector<std::string> names = {nameOf(a.summary), nameOf(b.summary)};
  py::gil_scoped_release release;  // a and b are kept alive by the caller's references
  return {mergeSummaries({&a.summary, &b.summary}, names), {}};
}

SummaryResult fromText(const std::string& text, const std::string& name) {
  return {summaryFrom(parseJson(text, name), name), {}};
}

py::list sourcesOf(const Summary& s) {
  py::list out;
  for (const SummarySource& source : s.sources) {
    py::dict d;
    d["file"] = source.file;
    d["sha256"] = source.sha256;
    d["samples"] = source.samples;
    d["rest_velocity"] = source.rest_velocity;
    d["torque_filter"] = source.torque_filter.active()
                             ? py::object(py::str(source.torque_filter.describe()))
                             : py::object(py::none());
    out.append(d);
  }
  return out;
}

void bindSummary(py::module_& m) {
  py::class_<SummaryResult>(
      m, "Summary",
      "A least-squares summary of one robot's logs (`dynid summarize`): per batch of samples and "
      "joint, the triangular factor of the fit's rows, so that identify() on it gives what it "
      "gives on the logs themselves (ols, wls, pc). Merge with + (or sum()); pickles through its "
      "summary.json.")
      .def_property_readonly(
          "samples", [](const SummaryResult& r) { return r.summary.factors.numSamples(); },
          "The samples summarized.")
      .def_property_readonly(
          "num_batches", [](const SummaryResult& r) { return r.summary.factors.batches().size(); },
          "Its batches of consecutive samples (the covariance's).")
      .def(
          "_join_for",
          [](SummaryResult& r, int shares) {
            if (shares < 1) throw py::value_error("shares must be >= 1");
            py::gil_scoped_release release;
            r.summary.factors.joinBatchesBeyond(std::max(1, kMaxSummaryBatches / shares));
          },
          py::arg("shares"),
          "In place: neighbouring batches joined while there are more than kMaxSummaryBatches / "
          "`shares` (the Dask layer's tasks, whose `shares` summaries a merge tree then appends "
          "without joining).")
      .def_property_readonly(
          "sources", [](const SummaryResult& r) { return sourcesOf(r.summary); },
          "The logs it holds, as dicts of file, sha256, samples, rest_velocity and torque_filter.")
      .def_property_readonly(
          "model", [](const SummaryResult& r) { return r.summary.model; },
          "The robot it was made for (drive terms and parameters as given).")
      .def("__add__", &merged, py::arg("other"),
           "The two summaries as one (their logs' rows together). Raises InputError for another "
           "robot, drive terms or base parameters.")
      .def(
          "__radd__",
          [](const SummaryResult& r, const py::object& other) {
            if (py::isinstance<py::int_>(other) && other.cast<int>() == 0) return r;
            throw py::type_error("a Summary adds to a Summary (or to 0, as sum() starts)");
          },
          py::arg("other"))
      .def(
          "to_json",
          [](const SummaryResult& r) {
            return jsonText(withCall(summaryJson(r.summary), r.provenance), 1) + "\n";
          },
          "summary.json, as `dynid summarize` writes it.")
      .def_static(
          "load",
          [](const PathLike& path) {
            const std::string file = pathArg(path, "path");
            return fromText(readFile(file), file);
          },
          py::arg("path"), "A summary.json (dynid summarize) read back.")
      // Pickled as summary.json with its factors detached as raw binary64 (what a Dask transfer
      // moves: no base64, no decimal text), read back through the same checks.
      .def(py::pickle(
          [](const SummaryResult& r) {
            std::vector<double> values;
            const std::string doc =
                jsonText(withCall(summaryJson(r.summary, &values), r.provenance), -1);
            // One bytes object: the document's length (8 bytes), the document, the values.
            std::string state(sizeof(std::uint64_t), '\0');
            const std::uint64_t length = doc.size();
            std::memcpy(state.data(), &length, sizeof(length));
            state += doc;
            state.append(reinterpret_cast<const char*>(values.data()),
                         values.size() * sizeof(double));
            return py::bytes(state);
          },
          [](const py::bytes& pickled) {
            const std::string state = pickled;
            std::uint64_t length = 0;
            if (state.size() >= sizeof(length)) std::memcpy(&length, state.data(), sizeof(length));
            if (state.size() < sizeof(length) || length > state.size() - sizeof(length))
              throw py::value_error("a Summary's pickle is cut short");
            const std::string doc = state.substr(sizeof(length), length);
            const std::string raw = state.substr(sizeof(length) + length);
            if (raw.size() % sizeof(double) != 0)
              throw py::value_error("a Summary's pickled factors are not whole doubles");
            std::vector<double> values(raw.size() / sizeof(double));
            std::memcpy(values.data(), raw.data(), raw.size());
            return SummaryResult{summaryFrom(parseJson(doc, "<pickle>"), "<pickle>", &values), {}};
          }))
      .def("__repr__", [](const SummaryResult& r) {
        return "<dynid.Summary of " + std::to_string(r.summary.sources.size()) + " log(s), " +
               std::to_string(r.summary.factors.numSamples()) + " samples, " +
               std::to_string(r.summary.factors.batches().size()) + " batches>";
      });
}

}  // namespace

void bindRunsSummarize(py::module_& m) {
  bindSummary(m);
  m.def("summarize", &summarize, py::arg("model"), py::arg("data"),
        py::arg("rest_velocity") = py::none(), py::arg("torque_filter") = "auto",
        py::arg("samples") = StructuralOptions{}.samples,
        py::arg("seed") = StructuralOptions{}.seed,
        py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
        py::arg("robot_spec") = "",
        "The least-squares summary of one log (`data`: a dataset path, streamed, or a Dataset), "
        "as `dynid summarize`: its rows as identify fits them (`rest_velocity` and "
        "`torque_filter` as identify's). Summaries of logs merge with + and give identify() the "
        "concatenated logs' estimate.");
  m.def(
      "summarize_many",
      [](const py::args& args, const py::kwargs& kwargs) {
        return callDistributed("summarize_many", args, kwargs);
      },
      "The merged Summary of many logs on a Dask cluster. Arguments: model, logs, client=None (a "
      "distributed.Client; None: a local cluster of one worker per core), rest_velocity=None, "
      "torque_filter='auto', robot_spec='', retries=2, logs_per_task=4. A task per "
      "logs_per_task logs, merged as a tree in the logs' order (the same bits however the tasks "
      "ran). Returns "
      "SummarizeMany(summary, summarized, failed): a log that cannot be summarized is named with "
      "its error in `failed`, the rest go on. The Dask layer is dynid_distributed.py, beside "
      "this module.");
}

}  // namespace dynid::python
