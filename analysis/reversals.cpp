#include "analysis/reversals.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace dynid {

namespace {

/// The share of sum r^2 that the least-squares fit of a sign(dq) + b dq + c explains (0 when r or
/// the fit is degenerate).
double frictionShare(const Eigen::RowVectorXd& dq, const Eigen::RowVectorXd& r) {
  const Eigen::Index count = dq.size();
  Eigen::MatrixXd a(count, 3);
  for (Eigen::Index k = 0; k < count; ++k)
    a.row(k) << (dq[k] > 0.0 ? 1.0 : dq[k] < 0.0 ? -1.0 : 0.0), dq[k], 1.0;
  const double total = r.squaredNorm();
  if (!(total > 0.0)) return 0.0;
  const Eigen::Matrix3d normal = a.transpose() * a;
  const Eigen::Vector3d rhs = a.transpose() * r.transpose();
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
  if (ldlt.info() != Eigen::Success) return 0.0;
  const Eigen::Vector3d x = ldlt.solve(rhs);
  const double left = (r.transpose() - a * x).squaredNorm();
  return std::isfinite(left) ? std::clamp(1.0 - left / total, 0.0, 1.0) : 0.0;
}

}  // namespace

ReversalResidual reversalResidual(const Prediction& p) {
  ReversalResidual out;
  const Eigen::MatrixXd& dq = p.velocity;
  const int n = static_cast<int>(dq.rows()), count = static_cast<int>(dq.cols());
  if (count == 0 || p.measured.cols() != count || p.predicted.cols() != count) return out;
  out.samples = count;
  out.speed.resize(n);
  out.sample_share.setZero(n);
  out.residual_share.setZero(n);
  out.friction_share.setZero(n);
  for (int j = 0; j < n; ++j) {
    out.speed[j] = kReversalSpeedFraction * std::sqrt(dq.row(j).squaredNorm() / count);
    double total = 0.0, inside = 0.0;
    int in_band = 0;
    for (int k = 0; k < count; ++k) {
      const double r = p.measured(j, k) - p.predicted(j, k);
      total += r * r;
      if (std::abs(dq(j, k)) < out.speed[j]) {
        inside += r * r;
        ++in_band;
      }
    }
    out.friction_share[j] = frictionShare(dq.row(j), p.measured.row(j) - p.predicted.row(j));
    if (out.friction_share[j] >= kFrictionResidualShare) out.friction_flagged.push_back(j);
    out.sample_share[j] = static_cast<double>(in_band) / count;
    out.residual_share[j] = total > 0.0 ? inside / total : 0.0;
    if (out.residual_share[j] >= kReversalResidualShare &&
        out.residual_share[j] >= kReversalConcentration * out.sample_share[j])
      out.flagged.push_back(j);
  }
  return out;
}

}  // namespace dynid
