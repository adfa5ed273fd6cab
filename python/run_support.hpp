// What the bindings of long runs share (python/bind_*.cpp): Ctrl-C and progress callbacks
// (Interrupt), per-joint options, GC segment settings, a dataset argument's trajectory, and a
// document as a Python object.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/records/provenance.hpp"
#include "core/integrators.hpp"
#include "core/run_control.hpp"
#include "data/dataset_csv.hpp"
#include "data/json_number.hpp"
#include "identifiability/least_squares.hpp"
#include "python/common.hpp"
#include "search/gc_error.hpp"

namespace dynid::python {

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
  /// `control`'s stop flag this one's, its progress lines reported as {"line": ...} to
  /// `callback` (setCallback's): a run whose progress is plain lines.
  void connect(RunControl& control, const py::object& callback) {
    setCallback(callback);
    control.stop = flag();
    control.progress = [this](const std::string& line) {
      report([&] {
        py::dict d;
        d["line"] = line;
        return d;
      });
    };
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
inline std::optional<Eigen::VectorXd> jointOption(const py::handle& value, const char* name,
                                                  int n) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value))
    return Eigen::VectorXd::Constant(n, value.cast<double>());
  return vectorArg(value, name, n);
}

inline SegmentOptions segmentOptions(double horizon, int segments, bool random_segments,
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
inline Trajectory trajectoryOf(const DataArg& d, const Model& model) {
  return d.arrays ? *d.arrays : readDatasetCsv(d.path, model.numJoints());
}

/// A document (nlohmann JSON) as the Python object json.loads gives.
inline py::object parsedJson(const nlohmann::json& document) {
  return py::module_::import("json").attr("loads")(document.dump());
}

/// A call's provenance (its documents' "provenance", records/provenance.hpp), begun where the call
/// starts (with the GIL held): interface "python", command [the function, "FILE:LINE" of the
/// calling Python code, that line of source (empty where there is none: an interactive line)],
/// the working directory, the files it was given (empty or "<arrays>"-like names: an argument in
/// memory, left out), its seed and threads. finish() when the run has returned: the files hashed,
/// the seconds it took.
class PythonRun {
 public:
  PythonRun(const std::string& function, std::vector<std::string> files,
            std::optional<std::uint64_t> seed = std::nullopt,
            std::optional<int> threads = std::nullopt);
  RunProvenance finish() const;

 private:
  RunProvenance run_;
  std::vector<std::string> files_;
  std::chrono::steady_clock::time_point start_;
};

/// `document` with the call's provenance (the kind its "kind" names); unchanged for a result that
/// no call made (`call` empty: read from a file).
nlohmann::json withCall(nlohmann::json document, const RunProvenance& call);

/// The Dask layer's function `name` (python/dynid_distributed.py, beside the module) called with
/// the arguments as given: what summarize_many, batch and fleet(client=) hand over to it.
inline py::object callDistributed(const char* name, const py::args& args,
                                  const py::kwargs& kwargs) {
  return py::module_::import("dynid_distributed").attr(name)(*args, **kwargs);
}

/// Each of a run's warnings as a Python UserWarning (with the GIL held), as the CLI prints them.
inline void warnAll(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, pythonText(w).c_str(), 1) < 0)
      throw py::error_already_set();  // warnings as errors
}

/// A Validation as a dict.
inline py::dict validationDict(const Validation& v) {
  py::dict d;
  d["num_samples"] = v.num_samples;
  d["torque_rms"] = toNumpy(v.torque_rms);
  d["normalised_rms"] = toNumpy(v.normalised_rms);
  d["relative_error"] = v.relative_error;
  return d;
}

}  // namespace dynid::python
