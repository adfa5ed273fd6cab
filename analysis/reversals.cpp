#include "analysis/reversals.hpp"

#include <cmath>

namespace dynid {

ReversalResidual reversalResidual(const Prediction& p) {
  ReversalResidual out;
  const Eigen::MatrixXd& dq = p.velocity;
  const int n = static_cast<int>(dq.rows()), count = static_cast<int>(dq.cols());
  if (count == 0 || p.measured.cols() != count || p.predicted.cols() != count) return out;
  out.samples = count;
  out.speed.resize(n);
  out.sample_share.setZero(n);
  out.residual_share.setZero(n);
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
    out.sample_share[j] = static_cast<double>(in_band) / count;
    out.residual_share[j] = total > 0.0 ? inside / total : 0.0;
    if (out.residual_share[j] >= kReversalResidualShare &&
        out.residual_share[j] >= kReversalConcentration * out.sample_share[j])
      out.flagged.push_back(j);
  }
  return out;
}

}  // namespace dynid
