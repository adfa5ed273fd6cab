#include "identifiability/floating/floating_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {

/// The rank rule on the unit-column rows' pivots (|R_jj| against the largest), the structural
/// analysis' (base_parameters.cpp's defaultTolerance): a combination that only round-off or a
/// recording's preparation errors excite (1e-14 of the largest, seen on a stand that never tilts)
/// is not determined on any compiler, where Eigen's default (p eps) made it a call at the edge.
constexpr double kRankTolerance = 1e-8;
/// The rows' noise covariance for one sample (floating_fit.hpp's table), with the torques'
/// variances `tv` (n) and the force rows' `fv` (J's rows).
Eigen::MatrixXd rowCovariance(SensorSet set, const FloatingMeasurement& m,
                              const Eigen::VectorXd& tv, const Eigen::VectorXd& fv) {
  const Eigen::Index nv = m.Y.rows(), n = nv - 6;
  Eigen::VectorXd joint = Eigen::VectorXd::Zero(nv);
  joint.tail(n) = tv;
  const Eigen::MatrixXd forces = m.J.rows() > 0
                                     ? Eigen::MatrixXd(m.J.transpose() * fv.asDiagonal() * m.J)
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

void checkSizes(const BaseParameters& base, const FloatingMeasurement& m) {
  if (m.tau.size() != m.Y.rows() - 6 || m.forces.size() != m.J.rows() ||
      m.force_variance.size() != m.J.rows() || m.Y.cols() != base.numStandard() ||
      (!m.moment_rows.empty() && static_cast<Eigen::Index>(m.moment_rows.size()) != m.J.rows()))
    throw InputError("a floating sample's sizes disagree: its regressor has " +
                     std::to_string(m.Y.rows()) + " rows and " + std::to_string(m.Y.cols()) +
                     " columns, " + std::to_string(m.tau.size()) + " torques, " +
                     std::to_string(m.forces.size()) + " contact forces for " +
                     std::to_string(m.J.rows()) + " Jacobian rows");
}

/// The samples' rows stacked (each block whitened by its covariance factor when `whiten` gives
/// one) and solved with unit-norm columns (base parameters differ by orders of magnitude: a
/// trunk's mass and a finger's inertia), then scaled back; the covariance s^2 (W^T W)^-1.
FloatingFit solveStacked(int p, const std::vector<Eigen::MatrixXd>& blocks,
                         const std::vector<Eigen::VectorXd>& values, int exact_rows = 0) {
  Eigen::Index rows = 0;
  for (const Eigen::MatrixXd& b : blocks) rows += b.rows();
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
  Eigen::VectorXd scale = W.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < p; ++c)
    if (scale[c] == 0.0) scale[c] = 1.0;
  const Eigen::MatrixXd scaled = W * scale.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled.rows(), scaled.cols());
  qr.setThreshold(kRankTolerance);
  qr.compute(scaled);
  if (qr.rank() < p) {
    const Eigen::VectorXd r = qr.matrixR().diagonal().cwiseAbs();
    throw InputError("the samples determine " + std::to_string(qr.rank()) + " of the " +
                     std::to_string(p) +
                     " base parameters: the motion does not excite them all (the least excited "
                     "combination at " +
                     formatNumber(r.minCoeff() / r.maxCoeff(), 2) + " of the most, at most " +
                     formatNumber(kRankTolerance) + " counts as unexcited)");
  }
  FloatingFit out;
  out.rows = static_cast<int>(rows);
  out.beta = qr.solve(y).cwiseQuotient(scale);
  const double rss = (W * out.beta - y).squaredNorm();
  // The near-constraint rows (factorCovariance) carry no noise: they are no residual degrees of
  // freedom.
  out.residual_scale =
      std::sqrt(rss / static_cast<double>(std::max<Eigen::Index>(rows - exact_rows - p, 1)));
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

const char* kNotPositive =
    "a floating sample's row covariance is not positive definite: a measured channel has zero "
    "noise variance";

/// The Cholesky factor of a sample's row covariance. Rows no noisy channel reaches (the base rows
/// in flight: nothing is measured there, the momentum equations hold as they are) have zero
/// variance: they are kept as near-constraints, with 1e-6 of the largest variance (an sd a
/// thousandth of the noisiest channel's: far stiffer than any measured row, and no more, so that
/// the normal equations keep their digits).
/// `exact_rows` counts them.
Eigen::LLT<Eigen::MatrixXd> factorCovariance(Eigen::MatrixXd C, int& exact_rows) {
  Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (llt.info() == Eigen::Success) return llt;
  const double largest = C.size() > 0 ? C.diagonal().maxCoeff() : 0.0;
  if (!(largest > 0.0)) throw InputError(kNotPositive);
  exact_rows += static_cast<int>((C.diagonal().array() <= 0.0).count());
  C.diagonal().array() += 1e-6 * largest;
  llt.compute(C);
  if (llt.info() != Eigen::Success) throw InputError(kNotPositive);
  return llt;
}
}  // namespace

FloatingFit fitFloating(const BaseParameters& base, SensorSet set,
                        const std::vector<FloatingMeasurement>& samples,
                        const FloatingFitOptions& options) {
  std::vector<Eigen::MatrixXd> blocks;
  std::vector<Eigen::VectorXd> values;
  int exact_rows = 0;
  for (const FloatingMeasurement& m : samples) {
    checkSizes(base, m);
    const Eigen::Index n = m.Y.rows() - 6;
    Eigen::MatrixXd W = base.baseRegressor(sensorRows(set, m.Y, m.J));
    Eigen::VectorXd y = sensorMeasurements(set, m.tau, m.J, m.forces);
    if (options.generalized) {
      const Eigen::VectorXd tv =
          options.torque_variance.size() == n ? options.torque_variance : Eigen::VectorXd::Ones(n);
      // Whitened by the covariance's Cholesky factor L (C = L L^T): L^-1 W, L^-1 y.
      const Eigen::LLT<Eigen::MatrixXd> llt =
          factorCovariance(rowCovariance(set, m, tv, m.force_variance), exact_rows);
      llt.matrixL().solveInPlace(W);
      llt.matrixL().solveInPlace(y);
    }
    blocks.push_back(std::move(W));
    values.push_back(std::move(y));
  }
  return solveStacked(base.numBase(), blocks, values, exact_rows);
}

namespace {
/// One sample's rows and measurements whitened by its row covariance at the channels' variances.
void whitenAt(SensorSet set, const FloatingMeasurement& m, const ChannelVariances& variances,
              Eigen::MatrixXd& W, Eigen::VectorXd& y, int& exact_rows) {
  Eigen::VectorXd fv(m.J.rows());
  for (Eigen::Index r = 0; r < fv.size(); ++r)
    fv[r] = !m.moment_rows.empty() && m.moment_rows[static_cast<std::size_t>(r)] ? variances.moment
                                                                                 : variances.force;
  const Eigen::LLT<Eigen::MatrixXd> llt = factorCovariance(
      rowCovariance(set, m, Eigen::VectorXd::Constant(m.tau.size(), variances.torque), fv),
      exact_rows);
  llt.matrixL().solveInPlace(W);
  llt.matrixL().solveInPlace(y);
}
}  // namespace

FloatingFit fitFloatingRows(SensorSet set, const std::vector<FloatingMeasurement>& samples,
                            const std::vector<Eigen::MatrixXd>& W,
                            const std::vector<Eigen::VectorXd>& y,
                            const ChannelVariances* variances) {
  if (W.size() != samples.size() || y.size() != samples.size() || W.empty())
    throw InputError("fitFloatingRows: one block of rows per sample, and one sample at least");
  std::vector<Eigen::MatrixXd> blocks = W;
  std::vector<Eigen::VectorXd> values = y;
  int exact_rows = 0;
  if (variances != nullptr)
    for (std::size_t k = 0; k < samples.size(); ++k)
      whitenAt(set, samples[k], *variances, blocks[k], values[k], exact_rows);
  return solveStacked(static_cast<int>(W.front().cols()), blocks, values, exact_rows);
}

Eigen::MatrixXd floatingStandardFactor(SensorSet set,
                                       const std::vector<FloatingMeasurement>& samples,
                                       const ChannelVariances* variances) {
  if (samples.empty()) throw InputError("floatingStandardFactor: no sample");
  const Eigen::Index p = samples.front().Y.cols();
  std::vector<Eigen::MatrixXd> blocks;
  Eigen::Index rows = 0;
  int exact_rows = 0;
  for (const FloatingMeasurement& m : samples) {
    if (m.Y.cols() != p)
      throw InputError("floatingStandardFactor: samples of " + std::to_string(p) + " and " +
                       std::to_string(m.Y.cols()) + " parameters");
    Eigen::MatrixXd W = sensorRows(set, m.Y, m.J);
    Eigen::VectorXd y = sensorMeasurements(set, m.tau, m.J, m.forces);
    if (variances != nullptr) whitenAt(set, m, *variances, W, y, exact_rows);
    blocks.emplace_back(W.rows(), p + 1);
    blocks.back() << W, y;
    rows += W.rows();
  }
  Eigen::MatrixXd stacked = Eigen::MatrixXd::Zero(std::max(rows, p + 1), p + 1);
  Eigen::Index at = 0;
  for (const Eigen::MatrixXd& b : blocks) {
    stacked.middleRows(at, b.rows()) = b;
    at += b.rows();
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stacked);
  return qr.matrixQR().topRows(p + 1).triangularView<Eigen::Upper>();
}

namespace {
/// One sample's rows and, per channel (torques, forces, moments), its row covariance at unit
/// variance (G_t, G_f, G_m).
struct SampleRows {
  Eigen::MatrixXd W;
  Eigen::VectorXd y;
  std::array<Eigen::MatrixXd, 3> G;
};

SampleRows sampleRows(const BaseParameters& base, SensorSet set, const FloatingMeasurement& m) {
  checkSizes(base, m);
  const Eigen::Index n = m.Y.rows() - 6, k = m.J.rows();
  SampleRows out{base.baseRegressor(sensorRows(set, m.Y, m.J)),
                 sensorMeasurements(set, m.tau, m.J, m.forces),
                 {}};
  Eigen::VectorXd forces(k), moments(k);
  for (Eigen::Index r = 0; r < k; ++r) {
    const bool moment = !m.moment_rows.empty() && m.moment_rows[static_cast<std::size_t>(r)];
    forces[r] = moment ? 0.0 : 1.0;
    moments[r] = moment ? 1.0 : 0.0;
  }
  out.G[0] = rowCovariance(set, m, Eigen::VectorXd::Ones(n), Eigen::VectorXd::Zero(k));
  out.G[1] = rowCovariance(set, m, Eigen::VectorXd::Zero(n), forces);
  out.G[2] = rowCovariance(set, m, Eigen::VectorXd::Zero(n), moments);
  return out;
}
}  // namespace

namespace {
/// The samples' rows whitened by C = sum_g variance_g G_g: each sample's factor, rows and values.
struct Whitened {
  std::vector<Eigen::LLT<Eigen::MatrixXd>> factors;
  std::vector<Eigen::MatrixXd> blocks;
  std::vector<Eigen::VectorXd> values;
  int rows = 0, exact_rows = 0;
};

Whitened whiten(const std::vector<SampleRows>& rows, const std::array<double, 3>& variance) {
  Whitened out;
  for (const SampleRows& s : rows) {
    Eigen::MatrixXd C = variance[0] * s.G[0];
    for (std::size_t g = 1; g < 3; ++g) C += variance[g] * s.G[g];
    out.factors.push_back(factorCovariance(std::move(C), out.exact_rows));
    out.blocks.push_back(out.factors.back().matrixL().solve(s.W));
    out.values.push_back(out.factors.back().matrixL().solve(s.y));
    out.rows += static_cast<int>(s.W.rows());
  }
  return out;
}

/// The least-squares solution by the normal equations (unit-scaled, a fourth of the QR's work:
/// for the iterations' weights; the reported fit is solveStacked's).
Eigen::VectorXd normalSolve(int p, const Whitened& w) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(p);
  for (std::size_t k = 0; k < w.blocks.size(); ++k) {
    A.selfadjointView<Eigen::Lower>().rankUpdate(w.blocks[k].transpose());
    b.noalias() += w.blocks[k].transpose() * w.values[k];
  }
  A.triangularView<Eigen::Upper>() = A.transpose();
  Eigen::VectorXd scale = A.diagonal().cwiseSqrt();
  for (Eigen::Index c = 0; c < p; ++c)
    if (scale[c] == 0.0) scale[c] = 1.0;
  const Eigen::MatrixXd scaled =
      scale.cwiseInverse().asDiagonal() * A * scale.cwiseInverse().asDiagonal();
  return scaled.ldlt().solve(b.cwiseQuotient(scale)).cwiseQuotient(scale);
}
}  // namespace

FloatingFit fitFloatingFeasible(const BaseParameters& base, SensorSet set,
                                const std::vector<FloatingMeasurement>& samples,
                                ChannelVariances* estimated) {
  std::vector<SampleRows> rows;
  for (const FloatingMeasurement& m : samples) rows.push_back(sampleRows(base, set, m));
  std::array<double, 3> variance = {1.0, 1.0, 1.0}, least = {0.0, 0.0, 0.0};
  const int p = base.numBase();
  {  // Rows that do not determine the parameters are refused before any weighting.
    const Whitened w = whiten(rows, variance);
    solveStacked(p, w.blocks, w.values, w.exact_rows);
  }
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Whitened w = whiten(rows, variance);
    const Eigen::VectorXd beta = normalSolve(p, w);
    std::array<double, 3> u{}, d{};
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Eigen::VectorXd z = w.factors[k].solve(Eigen::VectorXd(rows[k].W * beta - rows[k].y));
      for (std::size_t g = 0; g < 3; ++g) {
        u[g] += z.dot(rows[k].G[g] * z);
        d[g] += w.factors[k].solve(rows[k].G[g]).trace();
      }
    }
    const int noisy = w.rows - w.exact_rows;
    const double dof = static_cast<double>(noisy - p) / noisy;
    double change = 0.0;
    for (std::size_t g = 0; g < 3; ++g) {
      if (d[g] <= 0.0) continue;  // a channel the set does not read
      const double next = std::max(variance[g] * u[g] / (dof * d[g]), least[g]);
      change = std::max(change, std::abs(next - variance[g]) / variance[g]);
      variance[g] = next;
      // A channel the rows barely see (a sole's moments beside its forces' lever arms) can run
      // to zero, and C with it (two soles' forces alone cannot twist the base about the line
      // through them): each stays above 1e-6 of its first estimate.
      if (iteration == 0) least[g] = 1e-6 * next;
    }
    if (change < 1e-5) break;
  }
  if (estimated != nullptr) *estimated = {variance[0], variance[1], variance[2]};
  const Whitened w = whiten(rows, variance);
  return solveStacked(p, w.blocks, w.values, w.exact_rows);
}

}  // namespace dynid
