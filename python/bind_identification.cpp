// Identifiability (BaseParameters, base_parameters, identifiability) and identification
// (identify, predict): the pipelines of analysis/runs.hpp, the documents of reports/ as to_json().
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/audit.hpp"
#include "analysis/monitor.hpp"
#include "analysis/payload.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/payload_record.hpp"
#include "analysis/runs.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "python/common.hpp"
#include "reports/audit_report.hpp"
#include "reports/identification_report.hpp"
#include "reports/monitor_report.hpp"
#include "reports/payload_report.hpp"

namespace dynid::python {
namespace {

/// What `identifiability()` returns: the outcome and the model it describes (for to_json).
struct IdentifiabilityResult {
  Model model;
  IdentifiabilityOutcome outcome;
};

/// What `identify()` returns.
struct EstimateResult {
  Model model;  // the robot as given (its parameters are the prior)
  IdentifyOutcome outcome;
};

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
  py::array_t<double> time, measured, predicted;
  py::object band = py::none();  // (N, n) half widths, with an estimate's band
};

py::dict validationDict(const Validation& v) {
  py::dict d;
  d["num_samples"] = v.num_samples;
  d["torque_rms"] = toNumpy(v.torque_rms);
  d["normalised_rms"] = toNumpy(v.normalised_rms);
  d["relative_error"] = v.relative_error;
  return d;
}

StructuralOptions structural(int samples, std::uint64_t seed, double tolerance) {
  const StructuralOptions options{samples, seed, tolerance};
  options.check();
  return options;
}

std::vector<std::string> baseNames(const BaseParameters& b) {
  std::vector<std::string> out;
  for (int j = 0; j < b.numBase(); ++j) out.push_back(b.baseName(j));
  return out;
}

EstimateResult identify(const Model& model, const DataLike& data, const std::string& method,
                        const OptionalDataLike& validate, const std::optional<Model>& prior,
                        double prior_weight, int samples, std::uint64_t seed, double tolerance,
                        int threads, const PathLike& robot_spec,
                        const OptionalPathLike& validate_raw, std::optional<double> horizon,
                        std::optional<int> segments, std::optional<bool> raw_gc,
                        std::optional<double> combined_weight,
                        std::optional<double> combined_seconds,
                        std::optional<int> combined_iterations) {
  if (method != "pc" && method != "combined" && (prior || prior_weight != kDefaultPriorWeight))
    throw py::value_error("prior and prior_weight apply to methods 'pc' and 'combined', not '" +
                          method + "'");
  IdentifyRequest request;  // checked by identifyRun
  // The combined estimator's options, as identify's --horizon, --segments, --raw-gc,
  // --combined-weight, --combined-seconds and --combined-iterations (checked by identifyRun).
  if (method != "combined" &&
      (horizon || segments || raw_gc || combined_weight || combined_seconds || combined_iterations))
    throw py::value_error(
        "horizon, segments, raw_gc and combined_* apply to method 'combined', not '" + method +
        "'");
  if (horizon) request.segments.horizon = *horizon;
  if (segments) request.segments.num_segments = *segments;
  if (raw_gc) request.segments.normalise = !*raw_gc;
  if (combined_weight) request.combined.gc_weight = *combined_weight;
  if (combined_seconds) request.combined.max_seconds = *combined_seconds;
  if (combined_iterations) request.combined.max_iterations = *combined_iterations;
  request.model = model;
  request.method = parseMethod(method, identifyMethods());
  request.prior = prior;
  request.prior_weight = prior_weight;
  request.structural = structural(samples, seed, tolerance);
  request.threads = threads;
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  const DataArg train = dataArg(data, "data", model);
  request.data_file = train.path;
  request.data = train.arrays;
  if (!validate.is_none()) {
    const DataArg held = dataArg(validate, "validate", model);
    request.validate_file = held.path;
    request.validate = held.arrays;
  }
  if (!validate_raw.is_none()) request.validate_raw_file = pathArg(validate_raw, "validate_raw");
  EstimateResult out{model, {}};
  py::gil_scoped_release release;  // the Datasets are kept alive by the caller's references
  out.outcome = identifyRun(request);
  return out;
}

PredictionResult predict(const Model& model, const DataLike& data, int threads,
                         const EstimateResult* band_of) {
  checkThreads(threads);
  const DataArg d = dataArg(data, "data", model);
  const Model local = model;
  std::optional<PredictionBand> band;
  if (band_of) {
    const BaseEstimate& e = band_of->outcome.result.estimate;
    if (band_of->outcome.base.numStandard() != model.parameterLayout().size())
      throw py::value_error("band: the estimate is of another parameter layout than the model");
    band = PredictionBand{band_of->outcome.base.independent, e.covariance, e.joint_sigma};
  }
  CollectingSink sink;
  PredictionResult out;
  {
    py::gil_scoped_release release;
    ThreadPool pool(resolveThreads(threads));
    const PredictionBand* b = band ? &*band : nullptr;
    out.prediction = d.arrays ? predictTorques(local, *d.arrays, &pool, &sink, b)
                              : predictFile(local, d.path, pool, &sink, kStreamChunkSamples, b);
  }
  const py::ssize_t n = model.numJoints();
  out.time = sink.time();
  out.measured = sink.measured(n);
  out.predicted = sink.predicted(n);
  if (band) out.band = sink.band(n);
  return out;
}

void bindBaseParameters(py::module_& m) {
  py::class_<BaseParameters>(
      m, "BaseParameters",
      "Which combinations of the standard parameters the torques determine (Gautier's QR). "
      "beta = projection @ theta; regressor @ null_space == 0.")
      .def_property_readonly("names", &baseNames,
                             "Base parameter names, e.g. 'Izz1R' (R: others regrouped into it).")
      .def_readonly("standard_names", &BaseParameters::standard_names,
                    "The standard parameters' names in order (m1, mx1, ..., Izz1, then the drive "
                    "terms such as Fv1).")
      .def_property_readonly("num_base", &BaseParameters::numBase,
                             "The number of base parameters (the regressor's numerical rank).")
      .def_property_readonly("num_standard", &BaseParameters::numStandard,
                             "The number of standard parameters.")
      .def_readonly("independent", &BaseParameters::independent,
                    "Indices into the standard vector of the base parameters' leading terms.")
      .def_readonly("dependent", &BaseParameters::dependent,
                    "Indices into the standard vector of the parameters regrouped into others "
                    "(theta2), zero columns included.")
      .def_readonly("zero_columns", &BaseParameters::zero_columns,
                    "Standard parameters that never affect the torques.")
      .def_property_readonly(
          "K", [](const BaseParameters& b) { return toNumpy(b.K); },
          "The regrouping matrix, shape (num_base, len(dependent)): beta = theta1 + K @ theta2 "
          "[physical units].")
      .def_property_readonly(
          "projection", [](const BaseParameters& b) { return toNumpy(b.projectionMatrix()); },
          "P, shape (num_base, num_standard): beta = P @ theta.")
      .def_property_readonly(
          "null_space", [](const BaseParameters& b) { return toNumpy(b.nullSpace()); },
          "Basis of the unidentifiable directions, shape (num_standard, num_standard - num_base).")
      .def_property_readonly(
          "expressions",
          [](const BaseParameters& b) {
            std::vector<std::string> out;
            for (int j = 0; j < b.numBase(); ++j) out.push_back(b.expression(j));
            return out;
          },
          "Each base parameter as text, e.g. 'Izz1 + Iyy2 + 0.1865*m3'.")
      .def("combination", &BaseParameters::combination, py::arg("j"), py::arg("relative") = 1e-9,
           "[(standard name, coefficient), ...] of base parameter j, the leading one first.")
      .def_property_readonly(
          "rank_gap", &BaseParameters::rankGap,
          "The smallest kept |R_jj| over the largest dropped: how clearly the rank is determined "
          "(inf when nothing was dropped; below 1e4 the decision is close).")
      .def_readonly("tolerance", &BaseParameters::tolerance,
                    "The relative rank threshold used on the QR's |R_jj|.")
      .def_property_readonly(
          "significance", [](const BaseParameters& b) { return toNumpy(b.significance); },
          "Per standard parameter, the margin of the rank test (independent when > 1, 0 for a "
          "column that never acts), shape (num_standard,).")
      .def(
          "project",
          [](const BaseParameters& b, const ArrayLike& theta) {
            return toNumpy(b.project(vectorArg(theta, "theta", b.numStandard())));
          },
          py::arg("theta"), "beta = theta1 + K theta2 of a standard vector.")
      .def(
          "standard_from_base",
          [](const BaseParameters& b, const ArrayLike& beta, const ArrayLike& prior) {
            return toNumpy(b.standardFromBase(vectorArg(beta, "beta", b.numBase()),
                                              vectorArg(prior, "prior", b.numStandard())));
          },
          py::arg("beta"), py::arg("prior"),
          "A standard vector with these base values, the unseen directions from `prior`.")
      .def("__repr__", [](const BaseParameters& b) {
        return "<dynid.BaseParameters: " + std::to_string(b.numBase()) + " of " +
               std::to_string(b.numStandard()) + ">";
      });

  m.def(
      "base_parameters",
      [](const Model& model, int samples, std::uint64_t seed, double tolerance) {
        const StructuralOptions options = structural(samples, seed, tolerance);
        py::gil_scoped_release release;
        return structuralBaseParameters(model, options);
      },
      py::arg("model"), py::arg("samples") = StructuralOptions{}.samples,
      py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance,
      "The model's structural base parameters from `samples` seeded random states.");
}

void bindIdentifiability(py::module_& m) {
  py::class_<IdentifiabilityResult>(m, "Identifiability", "What `dynid identifiability` reports.")
      .def_property_readonly(
          "base", [](const IdentifiabilityResult& r) { return r.outcome.base; },
          "The base parameters (BaseParameters) of the model and joint ranges.")
      .def_property_readonly(
          "condition_number",
          [](const IdentifiabilityResult& r) { return r.outcome.condition_number; },
          "Of the unit-column base regressor on fresh random states.")
      .def_property_readonly(
          "model_beta",
          [](const IdentifiabilityResult& r) { return toNumpy(r.outcome.model_beta); },
          "The model's own base parameter values, shape (num_base,).")
      .def_property_readonly(
          "data",
          [](const IdentifiabilityResult& r) -> std::optional<py::dict> {
            if (!r.outcome.data) return std::nullopt;
            const DataExcitation& e = *r.outcome.data;
            py::dict d;
            d["file"] = e.file;
            d["samples"] = e.samples;
            d["condition_number"] = e.condition_number;
            d["rank"] = e.excitation.rank;
            d["r_diagonal"] = toNumpy(e.excitation.r_diagonal);
            std::vector<std::string> unexcited;
            for (int j : e.excitation.unexcited) unexcited.push_back(r.outcome.base.baseName(j));
            d["unexcited"] = unexcited;
            return d;
          },
          "How the dataset excites the base parameters, or None without one.")
      .def(
          "to_json",
          [](const IdentifiabilityResult& r) {
            return jsonText(identifiabilityJson(r.model, r.outcome), 2) + "\n";
          },
          "identifiability.json, as `dynid identifiability` writes it.");

  m.def(
      "identifiability",
      [](const Model& model, const OptionalDataLike& data, int samples, std::uint64_t seed,
         double tolerance, int threads) {
        checkThreads(threads);
        const StructuralOptions options = structural(samples, seed, tolerance);
        DataArg d;
        if (!data.is_none()) d = dataArg(data, "data", model);
        IdentifiabilityResult out{model, {}};
        py::gil_scoped_release release;
        out.outcome = identifiabilityRun(model, options, d.path, threads, d.arrays);
        return out;
      },
      py::arg("model"), py::arg("data") = py::none(),
      py::arg("samples") = StructuralOptions{}.samples, py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
      "Structural base parameters and conditioning, and with `data` (a path or a Dataset) how "
      "that dataset excites them.");
}

/// The Estimate class: estimate.json's fields, the identified model, its validation.
void bindEstimate(py::module_& m) {
  py::class_<EstimateResult>(m, "Estimate", "What `dynid identify` writes as estimate.json.")
      .def_property_readonly(
          "method",
          [](const EstimateResult& r) { return std::string(methodName(r.outcome.method)); },
          "The estimator, 'ols', 'wls', 'pc', 'combined', ... as `dynid identify --method`.")
      .def_property_readonly(
          "base", [](const EstimateResult& r) { return r.outcome.base; },
          "The base parameters (BaseParameters) the estimate is expressed in.")
      .def_property_readonly(
          "base_names", [](const EstimateResult& r) { return baseNames(r.outcome.base); },
          "The base parameters' names, e.g. 'Izz1R'.")
      .def_property_readonly(
          "beta", [](const EstimateResult& r) { return toNumpy(r.outcome.result.estimate.beta); },
          "The base parameter estimates (base_names order).")
      .def_property_readonly(
          "std_dev",
          [](const EstimateResult& r) { return toNumpy(r.outcome.result.estimate.std_dev); },
          "Each base parameter's standard deviation, shape (num_base,).")
      .def_property_readonly(
          "relative_std_dev_percent",
          [](const EstimateResult& r) {
            return toNumpy(r.outcome.result.estimate.relative_std_dev_percent);
          },
          "Each base parameter's standard deviation relative to its estimate [%], shape "
          "(num_base,).")
      .def_property_readonly(
          "covariance",
          [](const EstimateResult& r) { return toNumpy(r.outcome.result.estimate.covariance); },
          "The base parameters' covariance, shape (num_base, num_base).")
      .def_property_readonly(
          "condition_number",
          [](const EstimateResult& r) { return r.outcome.result.estimate.condition_number; },
          "The condition number of the (unit-column) base regressor on the data.")
      .def_property_readonly(
          "residual_rms",
          [](const EstimateResult& r) { return toNumpy(r.outcome.result.estimate.residual_rms); },
          "Each joint's RMS torque residual on the training data, shape (n,) [N m].")
      .def_property_readonly(
          "relative_error",
          [](const EstimateResult& r) { return r.outcome.result.estimate.relative_error; },
          "The relative torque error on the training data, ||tau - tau_hat|| / ||tau||.")
      .def_property_readonly(
          "num_samples",
          [](const EstimateResult& r) { return r.outcome.result.estimate.num_samples; },
          "The number of samples the estimate used.")
      .def_property_readonly(
          "standard", [](const EstimateResult& r) { return toNumpy(r.outcome.result.standard); },
          "A full standard vector (pc's own, or beta with the unseen directions from the prior).",
          "A full standard vector (pc's own, or beta with the unseen directions from the prior), "
          "shape (num_standard,).")
      .def_property_readonly(
          "standard_names", [](const EstimateResult& r) { return r.outcome.base.standard_names; },
          "The standard parameters' names, in the order of `standard`.")
      .def_property_readonly(
          "model",
          [](const EstimateResult& r) {
            Model identified = r.model;
            identified.setStandardParameters(r.outcome.result.standard);
            return identified;
          },
          "The robot with the estimated standard parameters (for predict, rnea, export).")
      .def_property_readonly(
          "validation",
          [](const EstimateResult& r) -> std::optional<py::dict> {
            if (!r.outcome.validation) return std::nullopt;
            return validationDict(*r.outcome.validation);
          },
          "On the held-out `validate` data, or None.")
      .def_property_readonly(
          "raw_validation",
          [](const EstimateResult& r) -> std::optional<py::dict> {
            if (!r.outcome.raw_validation) return std::nullopt;
            py::dict d = validationDict(*r.outcome.raw_validation);
            d["not_bracketed"] = r.outcome.raw_skipped;
            return d;
          },
          "Against the raw held-out torques (`validate_raw`) at the log's own stamps, or None.")
      .def_property_readonly(
          "violations",
          [](const EstimateResult& r) {
            std::vector<std::string> out;
            for (const ConsistencyViolation& v : r.outcome.violations)
              out.push_back(v.link_name + ": " + v.condition + " (" + v.detail + ")");
            return out;
          },
          "Links whose estimate is not physically consistent (empty for pc).")
      .def(
          "to_json",
          [](const EstimateResult& r) {
            return jsonText(estimateJson(r.model, r.outcome), 2) + "\n";
          },
          "estimate.json, as `dynid identify` writes it.");
}

void bindIdentify(py::module_& m) {
  m.def("identify", &identify, py::arg("model"), py::arg("data"), py::arg("method") = "ols",
        py::arg("validate") = py::none(), py::arg("prior") = py::none(),
        py::arg("prior_weight") = kDefaultPriorWeight,
        py::arg("samples") = StructuralOptions{}.samples,
        py::arg("seed") = StructuralOptions{}.seed,
        py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
        py::arg("robot_spec") = "", py::arg("validate_raw") = py::none(),
        py::arg("horizon") = py::none(), py::arg("segments") = py::none(),
        py::arg("raw_gc") = py::none(), py::arg("combined_weight") = py::none(),
        py::arg("combined_seconds") = py::none(), py::arg("combined_iterations") = py::none(),
        "Least-squares estimate of the base parameters from `data` (a CSV path, streamed, or a "
        "Dataset): method 'ols', 'wls', 'pc' (physically consistent, toward `prior`, default "
        "the model's own parameters) or 'combined' (pc's fit of the torques and the GC "
        "residuals of 100 normalised 50 ms rollouts together, at most 60 s; `horizon`, "
        "`segments`, `raw_gc`, `combined_weight`, `combined_seconds`, `combined_iterations` as "
        "identify's options). `validate`: held-out "
        "data; `validate_raw`: prepare's "
        "validate_raw.csv for it (keep_raw_torque=True), compared against too. `robot_spec` is "
        "recorded for "
        "`dynid predict`. Raises NumericalError when the data do not excite every base parameter.");
}

void bindPredict(py::module_& m) {
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
          "relative_error",
          [](const PredictionResult& r) { return r.prediction.validation.relative_error; },
          "The relative torque error ||tau - tau_hat|| / ||tau|| over every joint and sample.")
      .def_property_readonly(
          "num_samples",
          [](const PredictionResult& r) { return r.prediction.validation.num_samples; },
          "The number of samples compared.")
      .def_readonly("band", &PredictionResult::band,
                    "(N, n) half widths of the 95 % band [N m], or None without band=")
      .def_property_readonly(
          "band_coverage",
          [](const PredictionResult& r) -> std::optional<py::array_t<double>> {
            if (r.prediction.band_coverage.size() == 0) return std::nullopt;
            return toNumpy(r.prediction.band_coverage);
          },
          "(n,) the share of samples inside the band per joint, or None");

  m.def("predict", &predict, py::arg("model"), py::arg("data"), py::arg("threads") = kAllThreads,
        py::arg("band") = py::none(),
        "The model's torques on every sample of `data` (a path, streamed, or a Dataset) and the "
        "residual statistics of `dynid predict`. Use estimate.model for an estimate; band=estimate "
        "adds its 95 % band (base covariance and joint noise) and the coverage per joint.");
}

Eigen::Vector3d threeArg(const py::handle& value, const char* name) {
  return vectorArg(value, name, 3);
}

PayloadOutcome payload(const Model& model, const DataLike& data, const OptionalDataLike& unloaded,
                       const std::string& link, const OptionalArrayLike& tool_xyz,
                       const OptionalArrayLike& tool_rpy, const PriorLike& prior,
                       double prior_weight, bool refit_friction, const OptionalFloat& payload_mass,
                       const OptionalArrayLike& payload_com, double max_motion_difference) {
  PayloadRequest request;
  request.arm = model;
  request.arm_source = model.name;
  const DataArg loaded = dataArg(data, "data", model);
  request.data_file = loaded.path;
  request.data = loaded.arrays;
  if (!unloaded.is_none()) {
    const DataArg u = dataArg(unloaded, "unloaded", model);
    request.unloaded_file = u.path;
    request.unloaded = u.arrays;
  }
  request.link = link;
  if (!tool_xyz.is_none()) request.tool.translation = threeArg(tool_xyz, "tool_xyz");
  if (!tool_rpy.is_none()) {
    const Eigen::Vector3d rpy = threeArg(tool_rpy, "tool_rpy");
    request.tool.rotation = rotationFromRpy(rpy.x(), rpy.y(), rpy.z());
  }
  if (!prior.is_none()) {
    if (py::isinstance<py::str>(prior) || py::hasattr(prior, "__fspath__")) {
      const std::string file = pathArg(prior, "prior");
      request.prior = payloadBodyFrom(parseJson(readFile(file), file), file);
    } else {
      request.prior = vectorArg(prior, "prior", 10);
    }
  }
  request.prior_weight = prior_weight;
  request.refit_friction = refit_friction;
  if (!payload_mass.is_none()) request.known_mass = payload_mass.cast<double>();
  if (!payload_com.is_none()) request.known_com = threeArg(payload_com, "payload_com");
  request.max_motion_difference = max_motion_difference;
  py::gil_scoped_release release;  // the Datasets are kept alive by the caller's references
  return payloadRun(request);
}

void bindPayload(py::module_& m) {
  py::class_<PayloadOutcome>(m, "Payload",
                             "What dynid payload finds: the payload in the attachment frame.")
      .def_readonly("mode", &PayloadOutcome::mode, "'single' (one log) or 'difference'")
      .def_readonly("link", &PayloadOutcome::link_name, "the link it is attached to")
      .def_readonly("mass", &PayloadOutcome::mass, "[kg]")
      .def_property_readonly(
          "com", [](const PayloadOutcome& o) { return toNumpy(Eigen::VectorXd(o.com)); },
          "centre of mass in the attachment frame, (3,) [m]")
      .def_property_readonly(
          "inertia_com",
          [](const PayloadOutcome& o) { return toNumpy(Eigen::MatrixXd(o.inertia_com)); },
          "inertia about the centre of mass, attachment axes, (3, 3) [kg m^2]")
      .def_property_readonly(
          "principal_moments",
          [](const PayloadOutcome& o) { return toNumpy(Eigen::VectorXd(o.principal_moments)); },
          "(3,) [kg m^2], about principal_axes' columns")
      .def_property_readonly(
          "principal_axes",
          [](const PayloadOutcome& o) { return toNumpy(Eigen::MatrixXd(o.principal_axes)); },
          "(3, 3) rotation whose columns are the principal axes")
      .def_property_readonly(
          "standard", [](const PayloadOutcome& o) { return toNumpy(Eigen::VectorXd(o.standard)); },
          "the 10 standard parameters m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz (consistent)")
      .def_property_readonly(
          "covariance",
          [](const PayloadOutcome& o) { return toNumpy(Eigen::MatrixXd(o.covariance)); },
          "(10, 10) of the least-squares standard parameters (inf: not seen)")
      .def_property_readonly(
          "quantities",
          [](const PayloadOutcome& o) {
            py::list out;
            for (const PayloadQuantity& q : o.quantities) {
              py::dict d;
              d["name"] = q.name;
              d["group"] = q.group;
              d["unit"] = q.unit;
              d["value"] = q.value;
              d["std_dev"] = q.std_dev;
              d["half_width_95"] = q.half_width;
              d["determined"] = q.determined;
              out.append(d);
            }
            return out;
          },
          "every quantity with its 95 % interval and whether the log determines it")
      .def_readonly("unseen", &PayloadOutcome::unseen,
                    "combinations the motion does not excite at all")
      .def_readonly("combined", &PayloadOutcome::combined,
                    "combinations determined where their parts are not")
      .def_readonly("smallest_mass", &PayloadOutcome::smallest_mass,
                    "the smallest mass this log resolves to +-20 % (95 %) [kg]")
      .def_readonly("advice", &PayloadOutcome::advice,
                    "What to do about quantities the log does not determine (may be empty).")
      .def_readonly("warnings", &PayloadOutcome::warnings,
                    "Warnings about the log or the fit (may be empty).")
      .def_property_readonly(
          "gains",
          [](const PayloadOutcome& o) -> std::optional<py::dict> {
            if (!o.gains) return std::nullopt;
            py::dict d;
            d["scale"] = toNumpy(o.gains->scale);
            d["scale_std"] = toNumpy(o.gains->scale_std);
            py::list determined;
            for (char c : o.gains->determined) determined.append(c != 0);
            d["determined"] = determined;
            d["torque_constants"] = o.gains->torque_constants;
            return d;
          },
          "With payload_mass, per joint true / measured torque as a dict (scale, scale_std, "
          "determined, torque_constants; multiply the torque constants by scale), else None.")
      .def(
          "to_json", [](const PayloadOutcome& o) { return jsonText(payloadJson(o), 2) + "\n"; },
          "payload.json, as `dynid payload` writes it.")
      .def(
          "vendor",
          [](const PayloadOutcome& o, const std::string& format) {
            return payloadVendorFile(o, format).second;
          },
          py::arg("format"),
          "The payload in a controller's convention: 'ur', 'franka', 'kuka', 'abb' or 'json' "
          "(docs/PAYLOAD.md).");

  m.def("payload", &payload, py::arg("model"), py::arg("data"), py::arg("unloaded") = py::none(),
        py::arg("link") = "", py::arg("tool_xyz") = py::none(), py::arg("tool_rpy") = py::none(),
        py::arg("prior") = py::none(), py::arg("prior_weight") = PayloadRequest{}.prior_weight,
        py::arg("refit_friction") = false, py::arg("payload_mass") = py::none(),
        py::arg("payload_com") = py::none(),
        py::arg("max_motion_difference") = PayloadRequest{}.max_motion_difference,
        "What was added at `link` (default: the last) of the identified arm `model`, from `data` "
        "(a path or Dataset with the payload attached) and optionally `unloaded` (the same "
        "motion without it: the torque difference is used). `tool_xyz`/`tool_rpy`: the "
        "attachment frame in the link's frame. `prior`: a payload.json / payload.body.json path "
        "or 10 standard parameters. With `payload_mass` (and `unloaded`): the drives' torque "
        "constant scale factors (`gains`). As `dynid payload`.");
}

py::object parsedJson(const nlohmann::json& document) {
  return py::module_::import("json").attr("loads")(document.dump());
}

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
  return parsedJson(monitorJson(out));
}

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

void bindTrust(py::module_& m) {
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
  m.def("audit", &audit, py::arg("estimates") = py::none(), py::arg("data") = py::none(),
        py::arg("robot") = "", py::arg("drive_terms") = "", py::arg("method") = "ols",
        py::arg("level") = kDefaultAuditLevel, py::arg("threads") = kAllThreads,
        "`dynid audit`: estimate.json paths, or log paths identified with `robot`, "
        "`drive_terms` and `method`. Returns audit.json as a dict (per-parameter tests, verdict).");
}

}  // namespace

void bindIdentification(py::module_& m) {
  bindBaseParameters(m);
  bindIdentifiability(m);
  bindEstimate(m);
  bindIdentify(m);
  bindPredict(m);
  bindPayload(m);
  bindTrust(m);
}

}  // namespace dynid::python
