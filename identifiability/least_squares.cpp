#include "identifiability/least_squares.hpp"

#include <cmath>
#include <limits>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

LeastSquaresMethod parseLeastSquaresMethod(const std::string& name) {
  if (name == "ols") return LeastSquaresMethod::kOrdinary;
  if (name == "wls") return LeastSquaresMethod::kWeighted;
  throw InputError("unknown least-squares method '" + name + "' (expected ols or wls)");
}

const char* leastSquaresMethodName(LeastSquaresMethod method) {
  return method == LeastSquaresMethod::kOrdinary ? "ols" : "wls";
}

namespace {

/// Per-joint RMS of the rows k n + j of r.
Eigen::VectorXd jointRms(const Eigen::VectorXd& r, int n) {
  const Eigen::Index samples = r.size() / n;
  const Eigen::Map<const Eigen::MatrixXd> by_joint(r.data(), n, samples);
  return (by_joint.rowwise().squaredNorm() / static_cast<double>(samples)).cwiseSqrt();
}

struct Solution {
  Eigen::VectorXd beta, residual;
  Eigen::MatrixXd covariance_unit;  // (A^T A)^-1 in physical units for the weighted system
  double condition_number;
};

/// Solves diag(w) W1 beta = diag(w) tau, with w the per-joint row weights.
Solution solveWeighted(const Eigen::MatrixXd& W1, const Eigen::VectorXd& tau,
                       const Eigen::VectorXd& joint_weight) {
  const Eigen::Index rows = W1.rows(), b = W1.cols();
  const int n = static_cast<int>(joint_weight.size());
  Eigen::MatrixXd A = W1;
  Eigen::VectorXd y = tau;
  for (Eigen::Index r = 0; r < rows; ++r) {
    A.row(r) *= joint_weight[r % n];
    y[r] *= joint_weight[r % n];
  }
  // Unit-norm columns for accuracy: A = As D.
  const Eigen::VectorXd norms = A.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < b; ++j) A.col(j) /= norms[j];
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(b).triangularView<Eigen::Upper>();
  Solution out;
  out.beta = qr.solve(y).cwiseQuotient(norms);
  out.residual = tau - W1 * out.beta;
  // (As^T As)^-1 = R^-1 R^-T, unscaled by D^-1 on both sides.
  const Eigen::MatrixXd R_inverse =
      R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  out.covariance_unit =
      inv_norms.asDiagonal() * (R_inverse * R_inverse.transpose()) * inv_norms.asDiagonal();
  out.condition_number = scaledConditionNumber(A);
  return out;
}

}  // namespace

BaseEstimate estimateBaseParameters(const BaseParameters& base, const Observation& observation,
                                    LeastSquaresMethod method) {
  const int n = observation.num_joints, b = base.numBase();
  const Eigen::MatrixXd W1 = base.baseRegressor(observation.W);
  if (W1.rows() < b)
    throw InputError("the data has " + std::to_string(W1.rows()) + " torque rows, fewer than the " +
                     std::to_string(b) + " base parameters");
  const Excitation excitation = measureExcitation(W1);
  if (!excitation.unexcited.empty()) {
    std::string names;
    for (int j : excitation.unexcited) names += (names.empty() ? "" : ", ") + base.baseName(j);
    throw NumericalError("the data do not excite " + std::to_string(excitation.unexcited.size()) +
                         " of the " + std::to_string(b) + " base parameters (" + names +
                         "): rank " + std::to_string(excitation.rank) + " < " + std::to_string(b) +
                         "; refusing to solve a rank-deficient problem");
  }
  BaseEstimate out;
  out.method = method;
  out.num_samples = observation.num_samples;
  // OLS first: its residuals give the per-joint noise for WLS.
  Solution ols = solveWeighted(W1, observation.tau, Eigen::VectorXd::Ones(n));
  const double dof_per_joint =
      static_cast<double>(observation.num_samples) - static_cast<double>(b) / n;
  const Eigen::VectorXd rms = jointRms(ols.residual, n);
  out.joint_sigma =
      (rms.array().square() * (observation.num_samples / std::max(dof_per_joint, 1.0))).sqrt();
  Solution chosen;
  if (method == LeastSquaresMethod::kOrdinary) {
    const double sigma2 =
        ols.residual.squaredNorm() / std::max(static_cast<double>(W1.rows() - b), 1.0);
    chosen = std::move(ols);
    out.covariance = sigma2 * chosen.covariance_unit;
  } else {
    // A joint whose residual vanishes (noise-free data) gets a floor, not an infinite weight.
    Eigen::VectorXd sigma = out.joint_sigma;
    const double floor = 1e-15 * (1.0 + observation.tau.cwiseAbs().maxCoeff());
    for (Eigen::Index j = 0; j < n; ++j) sigma[j] = std::max(sigma[j], floor);
    chosen = solveWeighted(W1, observation.tau, sigma.cwiseInverse());
    out.covariance = chosen.covariance_unit;
  }
  out.beta = chosen.beta;
  out.condition_number = chosen.condition_number;
  out.std_dev = out.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.relative_std_dev_percent.resize(b);
  for (int j = 0; j < b; ++j)
    out.relative_std_dev_percent[j] = out.beta[j] != 0.0
                                          ? 100.0 * out.std_dev[j] / std::abs(out.beta[j])
                                          : std::numeric_limits<double>::infinity();
  out.residual_rms = jointRms(chosen.residual, n);
  return out;
}

Validation validateBaseEstimate(const BaseParameters& base, const Eigen::VectorXd& beta,
                                const Observation& observation) {
  const int n = observation.num_joints;
  if (beta.size() != base.numBase())
    throw InputError("base estimate has " + std::to_string(beta.size()) + " entries, expected " +
                     std::to_string(base.numBase()));
  const Eigen::VectorXd residual = observation.tau - base.baseRegressor(observation.W) * beta;
  Validation out;
  out.num_samples = observation.num_samples;
  out.torque_rms = jointRms(residual, n);
  const Eigen::VectorXd tau_rms = jointRms(observation.tau, n);
  out.normalised_rms.resize(n);
  for (int j = 0; j < n; ++j)
    out.normalised_rms[j] =
        tau_rms[j] > 0.0 ? out.torque_rms[j] / tau_rms[j] : std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace dynid
