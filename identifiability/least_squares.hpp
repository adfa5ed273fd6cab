// Least-squares identification of the base parameters from torque data, W1 beta = tau.
#pragma once

#include <string>

#include <Eigen/Core>

#include "identifiability/base_estimate.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

/// Estimates beta from an observation (rows k n + j). OLS: sigma^2 = |r|^2 / (nN - b),
/// covariance sigma^2 (W1^T W1)^-1. WLS: sigma_j^2 = |r_j|^2 / (N - b/n) from the OLS residuals of
/// joint j, rows weighted by 1/sigma_j, covariance (W1^T G^-1 W1)^-1 with G = diag(sigma_j^2).
/// Solved by Householder QR of the column-scaled regressor. Throws NumericalError when the data do
/// not excite every base parameter (naming the unexcited ones; rank-deficient data is never
/// solved), InputError when the observation has fewer rows than base parameters.
/// Per-joint RMS of a stacked vector (rows k n + j: n joints, r.size() / n samples; zero for none).
Eigen::VectorXd jointRms(const Eigen::VectorXd& r, int n);

BaseEstimate estimateBaseParameters(const BaseParameters& base, const Observation& observation,
                                    LeastSquaresMethod method);

/// Torque prediction W1 beta against a held-out observation.
Validation validateBaseEstimate(const BaseParameters& base, const Eigen::VectorXd& beta,
                                const Observation& observation);

}  // namespace dynid
