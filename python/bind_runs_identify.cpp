// The runs wing's identification rooms: base parameters and identifiability, and identify
// (analysis/runs/identify.hpp), its documents (reports/) as to_json(). predict:
// bind_runs_predict.cpp.
#include <cmath>
#include <optional>
#include <tuple>

#include <pybind11/stl.h>

#include "analysis/estimation/front.hpp"
#include "analysis/records/document.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/identify.hpp"
#include "analysis/runs/predict.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "python/estimate_result.hpp"
#include "python/run_support.hpp"
#include "python/summary_result.hpp"
#include "reports/identification_report.hpp"
#include "reports/prediction_report.hpp"

namespace dynid::python {
namespace {

/// What `identifiability()` returns: the outcome and the model it describes (for to_json).
struct IdentifiabilityResult {
  Model model;
  IdentifiabilityOutcome outcome;
  RunProvenance provenance;  // the call that made it
};

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

EstimateResult identify(
    const Model& model, const TrainingLike& data, const std::string& method,
    const OptionalDataLike& validate, const std::optional<Model>& prior, double prior_weight,
    int samples, std::uint64_t seed, double tolerance, int threads, const PathLike& robot_spec,
    const OptionalPathLike& validate_raw, std::optional<double> horizon,
    std::optional<int> segments, std::optional<bool> raw_gc, std::optional<double> combined_weight,
    std::optional<double> combined_seconds, std::optional<int> combined_iterations,
    const std::optional<std::vector<double>>& rest_velocity, const std::string& covariance,
    const TorqueFilterLike& torque_filter, bool front,
    const std::optional<std::vector<double>>& front_weights, double front_tolerance) {
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
  // identify's --front, --front-weights, --front-tolerance (checked by identifyRun).
  if (front_weights)
    request.front_weights = *front_weights;
  else if (front)
    request.front_weights = defaultFrontWeights();
  if (request.front_weights.empty() && front_tolerance != request.front_tolerance)
    throw py::value_error("front_tolerance applies with front=True or front_weights");
  request.front_tolerance = front_tolerance;
  request.model = model;
  request.method = parseMethod(method, identifyMethods());
  request.prior = prior;
  request.prior_weight = prior_weight;
  request.structural = structural(samples, seed, tolerance);
  request.threads = threads;
  if (rest_velocity) request.rest_velocity = *rest_velocity;
  try {
    request.covariance = covariancePolicyFrom(covariance);
  } catch (const InputError& e) {
    throw py::value_error(std::string("covariance: ") + e.what());
  }
  request.torque_filter = torqueFilterArg(torque_filter);
  request.robot_spec = pathArg(robot_spec, "robot_spec");
  if (py::isinstance<SummaryResult>(data)) {  // kept alive by the caller's reference
    if (rest_velocity || !py::isinstance<py::str>(torque_filter) ||
        torque_filter.cast<std::string>() != "auto")
      throw py::value_error(
          "rest_velocity and torque_filter apply to a dataset: a Summary holds each log's own");
    request.summary = &data.cast<const SummaryResult&>().summary;
    request.summary_name = "<summary>";
  } else {
    const DataArg train = dataArg(data, "data", model);
    request.data_file = train.path;
    request.data = train.arrays;
  }
  if (!validate.is_none()) {
    const DataArg held = dataArg(validate, "validate", model);
    request.validate_file = held.path;
    request.validate = held.arrays;
  }
  if (!validate_raw.is_none()) request.validate_raw_file = pathArg(validate_raw, "validate_raw");
  // combined stops at its next rollout on Ctrl-C (KeyboardInterrupt), keeping its best so far.
  Interrupt interrupt;
  request.combined.control.stop = interrupt.flag();
  request.combined.control.on_check = [&] { interrupt.poll(); };
  EstimateResult out{model, {}, {}};
  const PythonRun call("identify",
                       {request.data_file, request.validate_file, request.validate_raw_file}, seed,
                       threads);
  {
    py::gil_scoped_release release;  // the Datasets are kept alive by the caller's references
    out.outcome = identifyRun(request);
    out.provenance = call.finish();
  }
  interrupt.warnIfStopped();
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
            return jsonText(withCall(identifiabilityJson(r.model, r.outcome), r.provenance), 2) +
                   "\n";
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
        IdentifiabilityResult out{model, {}, {}};
        const PythonRun call("identifiability", {d.path}, seed, threads);
        py::gil_scoped_release release;
        out.outcome = identifiabilityRun(model, options, d.path, threads, d.arrays);
        out.provenance = call.finish();
        return out;
      },
      py::arg("model"), py::arg("data") = py::none(),
      py::arg("samples") = StructuralOptions{}.samples, py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
      "Structural base parameters and conditioning, and with `data` (a path or a Dataset) how "
      "that dataset excites them.");
}

/// The Estimate class: estimate.json's fields, the identified model, its validation.
/// Estimate's standard vector, model, fit, validation and document.
void bindEstimateDetails(py::class_<EstimateResult>& estimate) {
  estimate
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
            identified.rest_velocities = restThresholds(r.outcome.rest);
            return identified;
          },
          "The robot with the estimated standard parameters and the rest velocities measured on "
          "the training data (for predict, rnea, export).")
      .def_property_readonly(
          "rest_velocity",
          [](const EstimateResult& r) {
            const std::vector<double> v = restThresholds(r.outcome.rest);
            return toNumpy(Eigen::VectorXd(
                Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()))));
          },
          "(n,) each joint's rest velocity [rad/s or m/s], measured on the training data (or "
          "given): within it Coulomb, asymmetry and Stribeck friction are static, predicted as "
          "zero and not fitted.")
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
      .def_property_readonly(
          "front",
          [](const EstimateResult& r) -> std::optional<py::list> {
            if (!r.outcome.front) return std::nullopt;
            const IdentifyFront& f = *r.outcome.front;
            py::list out;
            for (std::size_t k = 0; k < f.points.size(); ++k) {
              const IdentifyFrontPoint& p = f.points[k];
              py::dict d;
              d["weight"] = p.weight;
              d["torque_train"] = p.torque_train;
              d["torque_test"] = p.test.torque;
              d["gc_train"] = p.gc_train;
              d["gc_test"] = p.test.gc;
              d["chosen"] = static_cast<int>(k) == f.choice.index;
              out.append(d);
            }
            return out;
          },
          "Each point of the front, in weight order, as a dict (weight, torque_train and "
          "torque_test as relative torque errors, gc_train, gc_test, chosen); None without a "
          "front.")
      .def(
          "to_json",
          [](const EstimateResult& r) {
            return jsonText(withCall(estimateJson(r.model, r.outcome), r.provenance), 2) + "\n";
          },
          "estimate.json, as `dynid identify` writes it.");
}

void bindEstimate(py::module_& m) {
  py::class_<EstimateResult> estimate(m, "Estimate",
                                      "What `dynid identify` writes as estimate.json.");
  estimate
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
          "covariance_policy",
          [](const EstimateResult& r) {
            const CovarianceSummary& c = r.outcome.result.covariance;
            py::dict out;
            out["name"] = c.policy;
            out["batch"] = c.batch;
            out["inflation"] = c.inflation;
            out["autocorrelation"] = c.autocorrelation;
            return out;
          },
          "How `covariance` was computed: name ('hac' or 'white'), batch (samples per "
          "batch), inflation (median standard deviation over the white covariance's) and the "
          "residuals' autocorrelation at lags 1, 2, 4, ...")
      .def_property_readonly(
          "condition_number",
          [](const EstimateResult& r) { return r.outcome.result.estimate.condition_number; },
          "The condition number of the (unit-column) base regressor on the data.")
      .def_property_readonly(
          "residual_rms",
          [](const EstimateResult& r) { return toNumpy(r.outcome.result.estimate.residual_rms); },
          "Each joint's RMS torque residual on the training data, shape (n,) [N m].")
      .def_property_readonly(
          "relative_error_percent",
          [](const EstimateResult& r) { return 100.0 * r.outcome.result.estimate.relative_error; },
          "The relative torque error on the training data, 100 ||tau - tau_hat|| / ||tau|| [%], "
          "as the CLI prints it (estimate.json's relative_error is the fraction).")
      .def_property_readonly(
          "relative_error",
          [](const EstimateResult& r) {
            warnFraction();
            return r.outcome.result.estimate.relative_error;
          },
          "The fraction ||tau - tau_hat|| / ||tau||, deprecated (a DeprecationWarning says so): "
          "relative_error_percent names its unit.")
      .def_property_readonly(
          "num_samples",
          [](const EstimateResult& r) { return r.outcome.result.estimate.num_samples; },
          "The number of samples the estimate used.");
  bindEstimateDetails(estimate);
}

void bindIdentify(py::module_& m) {
  m.def(
      "identify", &identify, py::arg("model"), py::arg("data"), py::arg("method") = "ols",
      py::arg("validate") = py::none(), py::arg("prior") = py::none(),
      py::arg("prior_weight") = kDefaultPriorWeight,
      py::arg("samples") = StructuralOptions{}.samples, py::arg("seed") = StructuralOptions{}.seed,
      py::arg("tolerance") = StructuralOptions{}.tolerance, py::arg("threads") = kAllThreads,
      py::arg("robot_spec") = "", py::arg("validate_raw") = py::none(),
      py::arg("horizon") = py::none(), py::arg("segments") = py::none(),
      py::arg("raw_gc") = py::none(), py::arg("combined_weight") = py::none(),
      py::arg("combined_seconds") = py::none(), py::arg("combined_iterations") = py::none(),
      py::arg("rest_velocity") = py::none(), py::arg("covariance") = "hac",
      py::arg("torque_filter") = "auto", py::arg("front") = false,
      py::arg("front_weights") = py::none(),
      py::arg("front_tolerance") = IdentifyRequest{}.front_tolerance,
      "Least-squares estimate of the base parameters from `data` (a CSV path, streamed, a "
      "Dataset, or a Summary of logs, which gives their estimate: ols, wls or pc): method 'ols', "
      "'wls', 'pc' (physically consistent, toward `prior`, default "
      "the model's own parameters) or 'combined' (pc's fit of the torques and the GC "
      "residuals of 100 normalised 50 ms rollouts together, at most 60 s; `horizon`, "
      "`segments`, `raw_gc`, `combined_weight`, `combined_seconds`, `combined_iterations` as "
      "identify's options). `validate`: held-out "
      "data; `validate_raw`: prepare's "
      "validate_raw.csv for it (keep_raw_torque=True), compared against too. `robot_spec` is "
      "recorded for "
      "`dynid predict`. `rest_velocity`: one, or one per joint [rad/s or m/s]; default measured on "
      "`data` (identify's --rest-velocity). `covariance`: 'hac' (default: robust to correlated "
      "residuals, over batches of samples) or 'white' (identify's --covariance). "
      "`torque_filter`: the low-pass the training torque went through, whose effect on the "
      "friction columns that need sign(dq) the fit reproduces: 'auto' (the prepare.json beside "
      "a data file; none for a Dataset), 'none', a cutoff [Hz] (order 4) or (cutoff, order) "
      "(identify's --torque-filter). `front`, `front_weights`, `front_tolerance` (method "
      "'combined', with `validate`): the combined estimator at a sweep of GC weights, the "
      "estimate the one the held-out data choose (identify's --front; the result's `front`). "
      "Raises "
      "NumericalError when the data do not excite "
      "every base parameter.");
}

}  // namespace

void bindRunsIdentify(py::module_& m) {
  bindBaseParameters(m);
  bindIdentifiability(m);
  bindEstimate(m);
  bindIdentify(m);
}

}  // namespace dynid::python
