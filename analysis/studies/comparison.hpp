// Comparing estimates in the same coordinates: every method's model is measured against the same
// truth, training and held-out data, parameter form and base parameters, so that regressor and
// search estimates sit side by side in one table.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"

namespace dynid {

/// One row of the comparison table (summary.json's `methods`).
struct MethodMetrics {
  std::string key;                // ols, wls, pc, nlo, ga, hybrid, nlo_refined, ga_refined, ...
  double gc_error_initial = 0.0;  // training GC error of the method's start
  double gc_error_train = 0.0;    // training GC error of the estimate
  double gc_error_test = 0.0;     // held-out GC error of the estimate
  double torque_rms_test = 0.0;   // held-out RMS of tau - ID(q, dq, ddq) over all joints [N m]
  double param_error = 0.0;       // the paper's error over the search's free parameters, eq. (1)
  double base_param_error = 0.0;  // RMS relative error of the base parameters
  long evaluations = 0;           // GC evaluations (searches), LM iterations (refinement), 0
  double seconds = 0.0;           // wall time of the method itself
};
/// A comparison row: {gc_error_initial, gc_error_train, gc_error_test, torque_rms_test,
/// param_error, base_param_error, evaluations, seconds}; non-finite numbers are null.
nlohmann::json metricsJson(const MethodMetrics& m);

/// Measures estimates against a known truth. Holds references to its arguments (all but the truth,
/// which it reads once).
class Comparison {
 public:
  /// `space` defines the paper's parameter error (its form and free parameters); `base` the base
  /// parameters. The truth and every estimate share the space's structure.
  Comparison(const Model& truth, const ParameterSpace& space, const BaseParameters& base,
             const GcProblem& train, const GcProblem& test, const Trajectory& test_data,
             ThreadPool& pool);
  /// The row for `estimate` (a model with the truth's structure).
  MethodMetrics measure(const std::string& key, const Model& estimate, double gc_error_initial,
                        long evaluations, double seconds);
  double trainGc(const Model& model);
  double testGc(const Model& model);

 private:
  const ParameterSpace& space_;
  const BaseParameters& base_;
  const GcProblem& train_;
  const GcProblem& test_;
  const Trajectory& test_data_;
  ThreadPool& pool_;
  GcWorkspace workspace_;
  Eigen::VectorXd truth_full_, beta_true_;
};

}  // namespace dynid
