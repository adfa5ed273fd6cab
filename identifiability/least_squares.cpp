#include "identifiability/least_squares.hpp"

#include <cmath>
#include <limits>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/errors.hpp"
#include "identifiability/tall_qr.hpp"

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
  double condition_number_unscaled;
  Eigen::VectorXd r_diagonal;    // |R_jj| of the column-scaled A (unpivoted QR)
  Eigen::VectorXd independence;  // BaseEstimate::independence
};

constexpr Eigen::Index kBlockRows = 1024;

/// Rows [start, start + k) of W1 = W(:, columns), contiguous.
Eigen::MatrixXd baseBlock(const Eigen::MatrixXd& W, const std::vector<int>& columns,
                          Eigen::Index start, Eigen::Index k) {
  Eigen::MatrixXd block(k, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j)
    block.col(static_cast<Eigen::Index>(j)) = W.col(columns[j]).segment(start, k);
  return block;
}

/// Solves diag(w) W1 beta = diag(w) tau, with w the per-joint row weights and W1 = W(:, columns),
/// streaming W's rows: column norms, then the triangular factor of [A D^-1 | y] (unit-norm columns
/// for accuracy, A = diag(w) W1, y = diag(w) tau) by TallQr, then the residual. Memory O(b^2)
/// beyond W, time linear in the rows.
Solution solveWeighted(const Eigen::MatrixXd& W, const std::vector<int>& columns,
                       const Eigen::VectorXd& tau, const Eigen::VectorXd& joint_weight) {
  const Eigen::Index rows = W.rows(), b = static_cast<Eigen::Index>(columns.size());
  const int n = static_cast<int>(joint_weight.size());
  const auto weighted = [&](Eigen::Index start, Eigen::Index k, Eigen::MatrixXd& block,
                            Eigen::VectorXd& y) {
    block = baseBlock(W, columns, start, k);
    y = tau.segment(start, k);
    for (Eigen::Index r = 0; r < k; ++r) {
      const double w = joint_weight[(start + r) % n];
      block.row(r) *= w;
      y[r] *= w;
    }
  };
  Eigen::MatrixXd block;
  Eigen::VectorXd y;
  Eigen::VectorXd squared = Eigen::VectorXd::Zero(b);
  for (Eigen::Index start = 0; start < rows; start += kBlockRows) {
    weighted(start, std::min(kBlockRows, rows - start), block, y);
    squared += block.colwise().squaredNorm().transpose();
  }
  Eigen::VectorXd norms = squared.cwiseSqrt();
  for (Eigen::Index j = 0; j < b; ++j)
    if (norms[j] == 0.0) norms[j] = 1.0;  // an unexcited column: R_jj = 0 says so
  TallQr factor(b + 1, kBlockRows);
  Eigen::MatrixXd augmented;
  for (Eigen::Index start = 0; start < rows; start += kBlockRows) {
    const Eigen::Index k = std::min(kBlockRows, rows - start);
    weighted(start, k, block, y);
    augmented.resize(k, b + 1);
    augmented.leftCols(b) = block * norms.cwiseInverse().asDiagonal();
    augmented.col(b) = y;
    factor.add(augmented);
  }
  const Eigen::MatrixXd R_augmented = factor.r();
  const Eigen::MatrixXd R = R_augmented.topLeftCorner(b, b);
  Solution out;
  out.r_diagonal = R.diagonal().cwiseAbs();
  for (Eigen::Index j = 0; j < b; ++j)
    if (squared[j] == 0.0) out.r_diagonal[j] = 0.0;
  out.beta =
      R.triangularView<Eigen::Upper>().solve(R_augmented.col(b).head(b)).cwiseQuotient(norms);
  out.residual.resize(rows);
  for (Eigen::Index start = 0; start < rows; start += kBlockRows) {
    const Eigen::Index k = std::min(kBlockRows, rows - start);
    out.residual.segment(start, k) =
        tau.segment(start, k) - baseBlock(W, columns, start, k) * out.beta;
  }
  // (As^T As)^-1 = R^-1 R^-T, unscaled by D^-1 on both sides.
  const Eigen::MatrixXd R_inverse =
      R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
  // With unit columns, (As^T As)^-1 = R^-1 R^-T: its diagonal is the variance inflation factor.
  out.independence = R_inverse.rowwise().norm().cwiseInverse();
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  out.covariance_unit =
      inv_norms.asDiagonal() * (R_inverse * R_inverse.transpose()) * inv_norms.asDiagonal();
  // Singular values of R equal those of the column-scaled A.
  const auto condition = [](const Eigen::MatrixXd& m) {
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues();
    return s.size() == 0 || s[s.size() - 1] == 0.0 ? std::numeric_limits<double>::infinity()
                                                   : s[0] / s[s.size() - 1];
  };
  out.condition_number = condition(R);
  // R D is the triangular factor of A itself: the unscaled condition number.
  out.condition_number_unscaled = condition(R * norms.asDiagonal());
  return out;
}

}  // namespace

BaseEstimate estimateBaseParameters(const BaseParameters& base, const Observation& observation,
                                    LeastSquaresMethod method) {
  const int n = observation.num_joints, b = base.numBase();
  const Eigen::MatrixXd& W = observation.W;
  if (W.cols() != base.numStandard())
    throw InputError("observation matrix has " + std::to_string(W.cols()) + " columns, expected " +
                     std::to_string(base.numStandard()));
  if (W.rows() < b)
    throw InputError("the data has " + std::to_string(W.rows()) + " torque rows, fewer than the " +
                     std::to_string(b) + " base parameters");
  // OLS first: its factor measures the excitation, its residuals give the per-joint noise (WLS).
  Solution ols = solveWeighted(W, base.independent, observation.tau, Eigen::VectorXd::Ones(n));
  const Excitation excitation = excitationFromRDiagonal(ols.r_diagonal);
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
  const double dof_per_joint =
      static_cast<double>(observation.num_samples) - static_cast<double>(b) / n;
  const Eigen::VectorXd rms = jointRms(ols.residual, n);
  out.joint_sigma =
      (rms.array().square() * (observation.num_samples / std::max(dof_per_joint, 1.0))).sqrt();
  Solution chosen;
  if (method == LeastSquaresMethod::kOrdinary) {
    const double sigma2 =
        ols.residual.squaredNorm() / std::max(static_cast<double>(W.rows() - b), 1.0);
    chosen = std::move(ols);
    out.covariance = sigma2 * chosen.covariance_unit;
  } else {
    // A joint whose residual vanishes (noise-free data) gets a floor, not an infinite weight.
    Eigen::VectorXd sigma = out.joint_sigma;
    const double floor = 1e-15 * (1.0 + observation.tau.cwiseAbs().maxCoeff());
    for (Eigen::Index j = 0; j < n; ++j) sigma[j] = std::max(sigma[j], floor);
    chosen = solveWeighted(W, base.independent, observation.tau, sigma.cwiseInverse());
    out.covariance = chosen.covariance_unit;
  }
  out.beta = chosen.beta;
  out.condition_number = chosen.condition_number;
  out.condition_number_unscaled = chosen.condition_number_unscaled;
  out.independence = chosen.independence;
  out.std_dev = out.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.relative_std_dev_percent.resize(b);
  for (int j = 0; j < b; ++j)
    out.relative_std_dev_percent[j] = out.beta[j] != 0.0
                                          ? 100.0 * out.std_dev[j] / std::abs(out.beta[j])
                                          : std::numeric_limits<double>::infinity();
  out.residual_rms = jointRms(chosen.residual, n);
  out.measured_rms = jointRms(observation.tau, n);
  setRelativeErrors(out);
  return out;
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

Validation validateBaseEstimate(const BaseParameters& base, const Eigen::VectorXd& beta,
                                const Observation& observation) {
  const int n = observation.num_joints;
  if (beta.size() != base.numBase())
    throw InputError("base estimate has " + std::to_string(beta.size()) + " entries, expected " +
                     std::to_string(base.numBase()));
  if (observation.W.cols() != base.numStandard())
    throw InputError("observation matrix has " + std::to_string(observation.W.cols()) +
                     " columns, expected " + std::to_string(base.numStandard()));
  // tau - W1 beta as tau - W theta1, theta1 = beta at the independent columns (no copy of W1).
  Eigen::VectorXd theta1 = Eigen::VectorXd::Zero(base.numStandard());
  for (int j = 0; j < base.numBase(); ++j) theta1[base.independent[j]] = beta[j];
  const Eigen::VectorXd residual = observation.tau - observation.W * theta1;
  Validation out;
  out.num_samples = observation.num_samples;
  out.torque_rms = jointRms(residual, n);
  const Eigen::VectorXd tau_rms = jointRms(observation.tau, n);
  out.relative_error = tau_rms.norm() > 0.0 ? out.torque_rms.norm() / tau_rms.norm()
                                            : std::numeric_limits<double>::infinity();
  out.normalised_rms.resize(n);
  for (int j = 0; j < n; ++j)
    out.normalised_rms[j] =
        tau_rms[j] > 0.0 ? out.torque_rms[j] / tau_rms[j] : std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace dynid
