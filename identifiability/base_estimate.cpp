#include "identifiability/base_estimate.hpp"

#include <cmath>
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
  // The norms over all rows from the per-joint RMS, each joint weighted by its rows.
  const Eigen::VectorXd rows = e.fitted_rows.size() == n ? e.fitted_rows : Eigen::VectorXd::Ones(n);
  const double measured = std::sqrt(rows.dot(e.measured_rms.cwiseAbs2()));
  e.relative_error = measured > 0.0 ? std::sqrt(rows.dot(e.residual_rms.cwiseAbs2())) / measured
                                    : std::numeric_limits<double>::infinity();
}

}  // namespace dynid
