#include "identifiability/base_estimate.hpp"

#include <limits>

namespace dynid {

const char* leastSquaresMethodName(LeastSquaresMethod method) {
  return method == LeastSquaresMethod::kOrdinary ? "ols" : "wls";
}

void setRelativeErrors(BaseEstimate& e) {
  const Eigen::Index n = e.residual_rms.size();
  e.joint_relative_error.resize(n);
  for (Eigen::Index j = 0; j < n; ++j)
    e.joint_relative_error[j] = e.measured_rms[j] > 0.0 ? e.residual_rms[j] / e.measured_rms[j]
                                                        : std::numeric_limits<double>::infinity();
  // Every joint has the same number of samples: the norms over all rows from the per-joint RMS.
  const double measured = e.measured_rms.norm();
  e.relative_error =
      measured > 0.0 ? e.residual_rms.norm() / measured : std::numeric_limits<double>::infinity();
}

}  // namespace dynid
