#include "identifiability/floating/floating_fit.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

namespace {
/// The rows' noise covariance for one sample (floating_fit.hpp's table).
Eigen::MatrixXd rowCovariance(SensorSet set, const FloatingMeasurement& m,
                              const Eigen::VectorXd& torque_variance) {
  const Eigen::Index nv = m.Y.rows(), n = nv - 6;
  Eigen::VectorXd joint = Eigen::VectorXd::Zero(nv);
  joint.tail(n) = torque_variance;
  const Eigen::MatrixXd forces =
      m.J.rows() > 0 ? Eigen::MatrixXd(m.J.transpose() * m.force_variance.asDiagonal() * m.J)
                     : Eigen::MatrixXd::Zero(nv, nv);
  switch (set) {
    case SensorSet::kWrenches:
      return forces.topLeftCorner(6, 6);
    case SensorSet::kTorquesAndWrenches:
      return Eigen::MatrixXd(joint.asDiagonal()) + forces;
    case SensorSet::kTorquesAndContactFlags: {
      // N^T diag(0, S_t) N, N the rows' basis: the rows of the projection are N^T times (0, e_k).
      const Eigen::MatrixXd rows = sensorRows(set, Eigen::MatrixXd::Identity(nv, nv), m.J);  // N^T
      return rows * joint.asDiagonal() * rows.transpose();
    }
  }
  return Eigen::MatrixXd();
}
}  // namespace

FloatingFit fitFloating(const BaseParameters& base, SensorSet set,
                        const std::vector<FloatingMeasurement>& samples,
                        const FloatingFitOptions& options) {
  const int p = base.numBase();
  std::vector<Eigen::MatrixXd> blocks;
  std::vector<Eigen::VectorXd> values;
  Eigen::Index rows = 0;
  for (const FloatingMeasurement& m : samples) {
    const Eigen::Index n = m.Y.rows() - 6;
    if (m.tau.size() != n || m.forces.size() != m.J.rows() ||
        m.force_variance.size() != m.J.rows() || m.Y.cols() != base.numStandard())
      throw InputError("a floating sample's sizes disagree: its regressor has " +
                       std::to_string(m.Y.rows()) + " rows and " + std::to_string(m.Y.cols()) +
                       " columns, " + std::to_string(m.tau.size()) + " torques, " +
                       std::to_string(m.forces.size()) + " contact forces for " +
                       std::to_string(m.J.rows()) + " Jacobian rows");
    Eigen::MatrixXd W = base.baseRegressor(sensorRows(set, m.Y, m.J));
    Eigen::VectorXd y = sensorMeasurements(set, m.tau, m.J, m.forces);
    if (options.generalized) {
      const Eigen::VectorXd tv =
          options.torque_variance.size() == n ? options.torque_variance : Eigen::VectorXd::Ones(n);
      // Whitened by the covariance's Cholesky factor L (C = L L^T): L^-1 W, L^-1 y.
      const Eigen::LLT<Eigen::MatrixXd> llt(rowCovariance(set, m, tv));
      if (llt.info() != Eigen::Success)
        throw InputError(
            "a floating sample's row covariance is not positive definite: a "
            "measured channel has zero noise variance");
      llt.matrixL().solveInPlace(W);
      llt.matrixL().solveInPlace(y);
    }
    rows += W.rows();
    blocks.push_back(std::move(W));
    values.push_back(std::move(y));
  }
  if (rows <= p)
    throw InputError("the samples give " + std::to_string(rows) + " rows for " + std::to_string(p) +
                     " base parameters: record more samples");
  Eigen::MatrixXd W(rows, p);
  Eigen::VectorXd y(rows);
  rows = 0;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    W.middleRows(rows, blocks[k].rows()) = blocks[k];
    y.segment(rows, values[k].size()) = values[k];
    rows += blocks[k].rows();
  }
  // Solved with unit-norm columns (base parameters differ by orders of magnitude: a trunk's mass
  // and a finger's inertia), then scaled back.
  Eigen::VectorXd scale = W.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < p; ++c)
    if (scale[c] == 0.0) scale[c] = 1.0;
  const Eigen::MatrixXd scaled = W * scale.cwiseInverse().asDiagonal();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled);
  if (qr.rank() < p)
    throw InputError("the samples determine " + std::to_string(qr.rank()) + " of the " +
                     std::to_string(p) + " base parameters: the motion does not excite them all");
  FloatingFit out;
  out.rows = static_cast<int>(rows);
  out.beta = qr.solve(y).cwiseQuotient(scale);
  const double rss = (W * out.beta - y).squaredNorm();
  out.residual_scale = std::sqrt(rss / static_cast<double>(rows - p));
  // s^2 (W^T W)^-1 = s^2 D^-1 (Ws^T Ws)^-1 D^-1, Ws = W D^-1 the unit-column matrix (the
  // inverse taken where it is well conditioned).
  const Eigen::MatrixXd information = scaled.transpose() * scaled;
  const Eigen::VectorXd inverse_scale = scale.cwiseInverse();
  out.covariance = out.residual_scale * out.residual_scale * inverse_scale.asDiagonal() *
                   information.ldlt().solve(Eigen::MatrixXd::Identity(p, p)) *
                   inverse_scale.asDiagonal();
  out.sd = out.covariance.diagonal().cwiseSqrt();
  return out;
}

}  // namespace dynid
