// The runs wing's predict room (analysis/runs/predict.hpp): a model's torques on a dataset, its
// statistics, the band of an estimate and the torque filter reproduced.
#include <optional>
#include <vector>

#include <pybind11/stl.h>

#include "analysis/logs/rest.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/predict.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "python/estimate_result.hpp"
#include "python/run_support.hpp"

namespace dynid::python {
namespace {

/// Collects every predicted sample (predict()'s arrays).
class CollectingSink : public PredictionSink {
 public:
  void bands(const Eigen::MatrixXd& half_width) override {
    for (Eigen::Index k = 0; k < half_width.cols(); ++k)
      for (Eigen::Index j = 0; j < half_width.rows(); ++j) band_.push_back(half_width(j, k));
  }
  void samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
               const Eigen::MatrixXd& predicted) override {
    const Eigen::Index n = measured.rows();
    for (Eigen::Index k = 0; k < time.size(); ++k) {
      time_.push_back(time[k]);
      for (Eigen::Index j = 0; j < n; ++j) {
        measured_.push_back(measured(j, k));
        predicted_.push_back(predicted(j, k));
      }
    }
  }
  py::array_t<double> time() const { return vectorOf(time_, {}); }
  py::array_t<double> measured(py::ssize_t n) const { return vectorOf(measured_, {n}); }
  py::array_t<double> predicted(py::ssize_t n) const { return vectorOf(predicted_, {n}); }
  py::array_t<double> band(py::ssize_t n) const { return vectorOf(band_, {n}); }

 private:
  py::array_t<double> vectorOf(const std::vector<double>& v, std::vector<py::ssize_t> tail) const {
    py::ssize_t per = 1;
    for (py::ssize_t d : tail) per *= d;
    tail.insert(tail.begin(), static_cast<py::ssize_t>(v.size()) / per);
    py::array_t<double> out(tail);
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  }
  std::vector<double> time_, measured_, predicted_, band_;
};

/// predict()'s result: every sample's torques and the statistics.
struct PredictionResult {
  Prediction prediction;
  std::vector<RestVelocity> rest;
  TorqueFilter torque_filter;  // reproduced (inactive: none)
  std::string torque_filter_source;
  py::array_t<double> time, measured, predicted;
  py::object band = py::none();  // (N, n) half widths, with an estimate's band
};

PredictionResult predict(const Model& model, const DataLike& data, int threads,
                         const EstimateResult* band_of,
                         const std::optional<std::vector<double>>& rest_velocity,
                         const TorqueFilterLike& torque_filter) {
  checkThreads(threads);
  const DataArg d = dataArg(data, "data", model);
  Model local = model;
  PredictionResult out;
  {  // the rest velocities: given, or measured on the data (as dynid predict does)
    const Trajectory read = d.arrays ? Trajectory{} : readDatasetCsv(d.path, model.numJoints());
    const Trajectory& t = d.arrays ? *d.arrays : read;
    out.rest = rest_velocity ? givenRestVelocities(*rest_velocity, t.dq)
                             : measureRestVelocities(t.dq, t.time);
    local.rest_velocities = restThresholds(out.rest);
  }
  PredictionFilter filter = [&] {
    try {
      return predictionFilter(local, d.path, d.arrays ? &*d.arrays : nullptr,
                              torqueFilterArg(torque_filter));
    } catch (const InputError& e) {
      throw py::value_error(pythonText(e.what()));
    }
  }();
  out.torque_filter = filter.rows ? filter.filter : TorqueFilter{};
  out.torque_filter_source = pythonText(filter.source);
  const FitRows* rows = filter.rows ? &*filter.rows : nullptr;
  std::optional<PredictionBand> band;
  if (band_of) {
    const BaseEstimate& e = band_of->outcome.result.estimate;
    if (band_of->outcome.base.numStandard() != model.parameterLayout().size())
      throw py::value_error("band: the estimate is of another parameter layout than the model");
    band = PredictionBand{band_of->outcome.base.independent, e.covariance, e.joint_sigma};
  }
  CollectingSink sink;
  {
    py::gil_scoped_release release;
    ThreadPool pool(resolveThreads(threads));
    const PredictionBand* b = band ? &*band : nullptr;
    out.prediction = d.arrays
                         ? predictTorques(local, *d.arrays, &pool, &sink, b, rows)
                         : predictFile(local, d.path, pool, &sink, kStreamChunkSamples, b, rows);
  }
  const py::ssize_t n = model.numJoints();
  out.time = sink.time();
  out.measured = sink.measured(n);
  out.predicted = sink.predicted(n);
  if (band) out.band = sink.band(n);
  return out;
}

}  // namespace

void bindRunsPredict(py::module_& m) {
  py::class_<PredictionResult>(m, "Prediction", "Torques predicted by RNEA against measured ones.")
      .def_readonly("time", &PredictionResult::time, "(N,) [s]")
      .def_readonly("measured", &PredictionResult::measured, "(N, n) [N m]")
      .def_readonly("predicted", &PredictionResult::predicted, "(N, n) [N m]")
      .def_property_readonly(
          "torque_rms",
          [](const PredictionResult& r) { return toNumpy(r.prediction.validation.torque_rms); },
          "Each joint's RMS of measured minus predicted torque, shape (n,) [N m].")
      .def_property_readonly(
          "normalised_rms",
          [](const PredictionResult& r) { return toNumpy(r.prediction.validation.normalised_rms); },
          "Each joint's torque RMS error relative to its measured torque's RMS, shape (n,).")
      .def_property_readonly(
          "relative_error_percent",
          [](const PredictionResult& r) { return 100.0 * r.prediction.validation.relative_error; },
          "The relative torque error 100 ||tau - tau_hat|| / ||tau|| over every joint and sample "
          "[%], as the CLI prints it (prediction.json's relative_error is the fraction).")
      .def_property_readonly(
          "relative_error",
          [](const PredictionResult& r) {
            warnFraction();
            return r.prediction.validation.relative_error;
          },
          "The fraction ||tau - tau_hat|| / ||tau||, deprecated (a DeprecationWarning says so): "
          "relative_error_percent names its unit.")
      .def_property_readonly(
          "num_samples",
          [](const PredictionResult& r) { return r.prediction.validation.num_samples; },
          "The number of samples compared.")
      .def_property_readonly(
          "torque_filter",
          [](const PredictionResult& r) -> py::object {
            if (!r.torque_filter.active()) return py::none();
            return py::make_tuple(r.torque_filter.cutoff, r.torque_filter.order);
          },
          "(cutoff [Hz], order) of the filter the statistics reproduced, or None")
      .def_readonly("torque_filter_source", &PredictionResult::torque_filter_source,
                    "Where the filter came from, or why none was reproduced.")
      .def_readonly("band", &PredictionResult::band,
                    "(N, n) half widths of the 95 % band [N m], or None without band=")
      .def_property_readonly(
          "band_coverage",
          [](const PredictionResult& r) -> std::optional<py::array_t<double>> {
            if (r.prediction.band_coverage.size() == 0) return std::nullopt;
            return toNumpy(r.prediction.band_coverage);
          },
          "(n,) the share of samples inside the band per joint, or None")
      .def_property_readonly(
          "at_rest",
          [](const PredictionResult& r) {
            const RestPrediction& p = r.prediction.rest;
            const std::vector<double> v = restThresholds(r.rest);
            py::dict out;
            out["rest_velocity"] = toNumpy(Eigen::VectorXd(
                Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()))));
            out["samples"] = toNumpy(p.samples);
            out["band_low"] = toNumpy(p.band_lo);
            out["band_high"] = toNumpy(p.band_hi);
            out["residual_mean"] = toNumpy(p.residual_mean);
            out["residual_std"] = toNumpy(p.residual_std);
            out["measured_std"] = toNumpy(p.measured_std);
            out["within_band"] = toNumpy(p.within_band);
            out["moving_rms"] = toNumpy(p.moving_rms);
            return out;
          },
          "Per joint, the samples at rest (|dq| within rest_velocity, measured on the data or "
          "given): their count, the static friction band [band_low, band_high] [N m], the "
          "residual's mean and standard deviation there, the measured torque's standard deviation, "
          "the share of residuals inside the band, and the residual RMS in motion.");

  m.def("predict", &predict, py::arg("model"), py::arg("data"), py::arg("threads") = kAllThreads,
        py::arg("band") = py::none(), py::arg("rest_velocity") = py::none(),
        py::arg("torque_filter") = "auto",
        "The model's torques on every sample of `data` (a path, streamed, or a Dataset) and the "
        "residual statistics of `dynid predict`. Use estimate.model for an estimate; band=estimate "
        "adds its 95 % band (base covariance and joint noise) and the coverage per joint. "
        "`rest_velocity`: one, or one per joint; default measured on `data` (see at_rest). "
        "`torque_filter`: the low-pass the data's torque went through, which the statistics "
        "reproduce on the model's friction that needs sign(dq), as identify's held-out error "
        "does: 'auto' (the prepare.json beside a data file; none for a Dataset), 'none', a "
        "cutoff [Hz] or (cutoff, order); `predicted` stays the model's own torque.");
}

}  // namespace dynid::python
