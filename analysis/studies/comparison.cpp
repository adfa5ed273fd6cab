#include "analysis/studies/comparison.hpp"

#include <cmath>

#include "core/rnea.hpp"
#include "data/json_number.hpp"

namespace dynid {

Comparison::Comparison(const Model& truth, const ParameterSpace& space, const BaseParameters& base,
                       const GcProblem& train, const GcProblem& test, const Trajectory& test_data,
                       ThreadPool& pool)
    : space_(space),
      base_(base),
      train_(train),
      test_(test),
      test_data_(test_data),
      pool_(pool),
      workspace_(pool.numThreads()),
      truth_full_(space.fullVector(truth)),
      beta_true_(base.project(truth.standardParameters())) {}

double Comparison::trainGc(const Model& model) { return gcError(model, train_, workspace_, pool_); }
double Comparison::testGc(const Model& model) { return gcError(model, test_, workspace_, pool_); }

MethodMetrics Comparison::measure(const std::string& key, const Model& estimate,
                                  double gc_error_initial, long evaluations, double seconds) {
  MethodMetrics out;
  out.key = key;
  out.gc_error_initial = gc_error_initial;
  out.gc_error_train = gcError(estimate, train_, workspace_, pool_);
  out.gc_error_test = gcError(estimate, test_, workspace_, pool_);
  Data data(estimate);
  double squared = 0.0;
  for (int k = 0; k < test_data_.numSamples(); ++k)
    squared += (test_data_.tau.col(k) - rnea(estimate, data, test_data_.q.col(k),
                                             test_data_.dq.col(k), test_data_.ddq.col(k)))
                   .squaredNorm();
  out.torque_rms_test =
      std::sqrt(squared / std::max(1.0, static_cast<double>(test_data_.tau.size())));
  out.param_error = space_.parameterError(space_.freeOf(space_.fullVector(estimate)), truth_full_);
  out.base_param_error =
      baseParameterError(base_.project(estimate.standardParameters()), beta_true_);
  out.evaluations = evaluations;
  out.seconds = seconds;
  return out;
}

nlohmann::json metricsJson(const MethodMetrics& m) {
  return {{"gc_error_initial", numberOrNull(m.gc_error_initial)},
          {"gc_error_train", numberOrNull(m.gc_error_train)},
          {"gc_error_test", numberOrNull(m.gc_error_test)},
          {"torque_rms_test", numberOrNull(m.torque_rms_test)},
          {"param_error", numberOrNull(m.param_error)},
          {"base_param_error", numberOrNull(m.base_param_error)},
          {"evaluations", m.evaluations},
          {"seconds", numberOrNull(m.seconds)}};
}

}  // namespace dynid
