#include "analysis/estimation/reversals.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace dynid {

namespace {

/// The share of sum r^2 that the least-squares fit of a sign(dq) + b dq + c explains: from the
/// 3 x 3 normal equations accumulated over the samples (nothing stored per sample), as x^T A^T r
/// / r^T r. 0 when r is zero or the fit is degenerate (a joint at rest has sign(dq) = 0 and a
/// singular system: the pseudo-solution of the LDLT still gives the constant's share).
double frictionShare(const Eigen::MatrixXd& dq, const Eigen::MatrixXd& measured,
                     const Eigen::MatrixXd& predicted, int j, const ReversalMask* fitted) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (Eigen::Index k = 0; k < dq.cols(); ++k) {
    if (fitted && !(*fitted)(j, k)) continue;
    const double v = dq(j, k), r = measured(j, k) - predicted(j, k);
    const Eigen::Vector3d a(v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0, v, 1.0);
    normal.noalias() += a * a.transpose();
    rhs += r * a;
    total += r * r;
  }
  if (!(total > 0.0)) return 0.0;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
  if (ldlt.info() != Eigen::Success) return 0.0;
  const double explained = ldlt.solve(rhs).dot(rhs);
  return std::isfinite(explained) ? std::clamp(explained / total, 0.0, 1.0) : 0.0;
}

}  // namespace

ReversalResidual reversalResidual(const Prediction& p, const ReversalMask* fitted) {
  ReversalResidual out;
  const Eigen::MatrixXd& dq = p.velocity;
  const int n = static_cast<int>(dq.rows()), count = static_cast<int>(dq.cols());
  if (count == 0 || p.measured.cols() != count || p.predicted.cols() != count) return out;
  if (fitted && (fitted->rows() != n || fitted->cols() != count)) fitted = nullptr;
  out.samples = count;
  out.speed.resize(n);
  out.sample_share.setZero(n);
  out.residual_share.setZero(n);
  out.friction_share.setZero(n);
  for (int j = 0; j < n; ++j) {
    out.speed[j] = kReversalSpeedFraction * std::sqrt(dq.row(j).squaredNorm() / count);
    double total = 0.0, inside = 0.0, measured = 0.0;
    int in_band = 0, taken = 0;
    for (int k = 0; k < count; ++k) {
      if (fitted && !(*fitted)(j, k)) continue;
      ++taken;
      const double r = p.measured(j, k) - p.predicted(j, k);
      total += r * r;
      measured += p.measured(j, k) * p.measured(j, k);
      if (std::abs(dq(j, k)) < out.speed[j]) {
        inside += r * r;
        ++in_band;
      }
    }
    out.friction_share[j] = frictionShare(dq, p.measured, p.predicted, j, fitted);
    const bool above_round_off = total > kResidualAboveRoundOff * kResidualAboveRoundOff * measured;
    if (above_round_off && out.friction_share[j] >= kFrictionResidualShare)
      out.friction_flagged.push_back(j);
    out.sample_share[j] = taken > 0 ? static_cast<double>(in_band) / taken : 0.0;
    out.residual_share[j] = total > 0.0 ? inside / total : 0.0;
    if (above_round_off && out.residual_share[j] >= kReversalResidualShare &&
        out.residual_share[j] >= kReversalConcentration * out.sample_share[j])
      out.flagged.push_back(j);
  }
  return out;
}

ReversalMask fittedMask(const Prediction& prediction, const FitRows& rows) {
  const Eigen::Index n = prediction.velocity.rows(), count = prediction.velocity.cols();
  ReversalMask out(n, count);
  for (Eigen::Index k = 0; k < count; ++k)
    for (Eigen::Index j = 0; j < n; ++j)
      out(j, k) = rows.fitted(k * static_cast<long long>(prediction.stride), static_cast<int>(j),
                              prediction.velocity(j, k));
  return out;
}

}  // namespace dynid
