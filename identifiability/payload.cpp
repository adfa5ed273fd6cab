#include "identifiability/payload.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/errors.hpp"
#include "core/log_cholesky.hpp"
#include "core/memory.hpp"
#include "core/parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/physically_consistent.hpp"
#include "identifiability/uncertainty/score_covariance.hpp"

namespace dynid {

Matrix10d standardTransform(const Pose<double>& pose) {
  Matrix10d out;
  for (int k = 0; k < 10; ++k)
    out.col(k) = toStandardVector(fromStandardVector(Vector10d::Unit(k)).transformedBy(pose));
  return out;
}

PayloadRows::PayloadRows(int num_joints, int extra_columns)
    : n_(num_joints), extra_(extra_columns) {
  if (num_joints < 1 || extra_columns < 0)
    throw InputError("a payload problem needs at least one joint and no negative column count");
}

void PayloadRows::reserve(int samples) {
  const double bytes = static_cast<double>(samples) * n_ * (extra_ + 11) * sizeof(double);
  requireMemory(bytes, "the payload problem's rows");
  if (samples > samples_) {
    design_.conservativeResize(static_cast<Eigen::Index>(samples) * n_, extra_ + 10);
    target_.conservativeResize(static_cast<Eigen::Index>(samples) * n_);
  }
}

void PayloadRows::add(const Eigen::Ref<const Eigen::MatrixXd>& body,
                      const Eigen::Ref<const Eigen::MatrixXd>& extra,
                      const Eigen::Ref<const Eigen::VectorXd>& target) {
  if (body.rows() != n_ || body.cols() != 10 || extra.rows() != (extra_ > 0 ? n_ : extra.rows()) ||
      extra.cols() != extra_ || target.size() != n_)
    throw InputError("a payload sample has the wrong size");
  if (!body.allFinite() || !extra.allFinite() || !target.allFinite())
    throw InputError("a payload sample has a value that is not finite (sample " +
                     std::to_string(samples_ + 1) + ")");
  if (rows() + n_ > design_.rows()) reserve(std::max(2 * samples_, 1024));
  const Eigen::Index r = rows();
  if (extra_ > 0) design_.block(r, 0, n_, extra_) = extra;
  design_.block(r, extra_, n_, 10) = body;
  target_.segment(r, n_) = target;
  ++samples_;
}

namespace {

/// Per joint standard deviation of residuals with `unknowns` parameters fitted, floored at 1e-9 of
/// the largest joint's target RMS (noise-free data still needs finite weights).
Eigen::VectorXd jointNoise(const Eigen::VectorXd& residual, int n, int unknowns,
                           const Eigen::VectorXd& target_rms) {
  const double samples = static_cast<double>(residual.size() / n);
  const double dof = std::max(samples - static_cast<double>(unknowns) / n, 1.0);
  const Eigen::VectorXd rms = jointRms(residual, n);
  const double floor = 1e-9 * target_rms.maxCoeff() + 1e-300;
  return (rms * std::sqrt(samples / dof)).cwiseMax(floor);
}

/// The singular value decomposition of a small square matrix (no QR preconditioner: the matrix is
/// square, and the preconditioners would triple what this file compiles).
using SquareSvd = Eigen::JacobiSVD<Eigen::MatrixXd, Eigen::NoQRPreconditioner>;

/// Minimum-norm solution of the square system r x = c: singular values at most `relative` of the
/// largest count as zero.
Eigen::VectorXd minimumNorm(const SquareSvd& svd, const Eigen::VectorXd& c, double relative) {
  const Eigen::VectorXd& sigma = svd.singularValues();
  const double top = sigma.size() > 0 ? sigma[0] : 0.0;
  Eigen::VectorXd projected = svd.matrixU().transpose() * c;
  for (Eigen::Index k = 0; k < sigma.size(); ++k)
    projected[k] = sigma[k] > relative * top && sigma[k] > 0.0 ? projected[k] / sigma[k] : 0.0;
  return svd.matrixV() * projected;
}

/// Minimum-norm least squares in column-scaled coordinates: x = S argmin |A S z - b|, S = diag of
/// 1 / the column norms (1 for a zero column): the QR of [A S | b] reduces it to the square
/// triangular system, solved by its singular values (below 1e-12 of the largest: zero).
Eigen::VectorXd scaledSolve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const Eigen::Index d = A.cols();
  Eigen::VectorXd s = A.colwise().norm().transpose();
  for (Eigen::Index k = 0; k < d; ++k) s[k] = s[k] > 0.0 ? 1.0 / s[k] : 1.0;
  Eigen::MatrixXd M(std::max(A.rows(), d + 1), d + 1);
  M.setZero();
  M.topLeftCorner(A.rows(), d) = A * s.asDiagonal();
  M.col(d).head(A.rows()) = b;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  const Eigen::MatrixXd r = qr.matrixQR().topLeftCorner(d, d).triangularView<Eigen::Upper>();
  const SquareSvd svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return s.asDiagonal() * minimumNorm(svd, qr.matrixQR().col(d).head(d), 1e-12);
}

/// The sandwich covariance H^+ Omega H^+ of a least-squares estimate with whitened Jacobian
/// `jacobian` and residuals `residual` (rows k n + j): the one policy
/// (identifiability/uncertainty/score_covariance.hpp: robust over batches of samples; `batch` 0:
/// from the residuals, and set to the length used). When H does not see every direction (eigenvalue
/// below 1e-16 of the largest in unit-diagonal scaling), batch means of the scores about H's
/// pseudo-inverse, and a parameter with a component in an unseen direction gets infinite variance.
Eigen::MatrixXd sandwichCovariance(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                                   int n, int& batch) {
  const Eigen::Index d = jacobian.cols(), samples = residual.size() / n;
  const Eigen::MatrixXd h = jacobian.transpose() * jacobian;
  Eigen::VectorXd s = h.diagonal().cwiseSqrt();
  for (Eigen::Index k = 0; k < d; ++k) s[k] = s[k] > 0.0 ? 1.0 / s[k] : 1.0;
  const Eigen::MatrixXd hs = s.asDiagonal() * h * s.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(hs);
  const Eigen::VectorXd& l = eigen.eigenvalues();
  const double top = std::max(l.maxCoeff(), 1e-300);
  Eigen::VectorXd inverse(d);
  std::vector<int> unseen;
  for (Eigen::Index k = 0; k < d; ++k) {
    const bool seen = l[k] > 1e-16 * top;
    inverse[k] = seen ? 1.0 / l[k] : 0.0;
    if (!seen) unseen.push_back(static_cast<int>(k));
  }
  const Eigen::MatrixXd pinv = s.asDiagonal() * eigen.eigenvectors() * inverse.asDiagonal() *
                               eigen.eigenvectors().transpose() * s.asDiagonal();
  ScoreCovariance scores(d, n, samples, batch);
  for (Eigen::Index k = 0; k < samples; ++k)
    scores.add(jacobian.middleRows(k * n, n), residual.segment(k * n, n));
  batch = scores.batch();
  // Every direction seen: the policy's covariance; otherwise batch means about the
  // pseudo-inverse (the unseen directions' variance is infinite below).
  Eigen::MatrixXd out;
  try {
    out = unseen.empty() ? scores.covariance() : pinv * scores.meat() * pinv;
  } catch (const NumericalError&) {  // seen, but too ill-conditioned to factor
    out = pinv * scores.meat() * pinv;
  }
  for (int k : unseen)
    for (Eigen::Index i = 0; i < d; ++i)
      if (std::abs(eigen.eigenvectors()(i, k)) > 1e-6) {
        out.row(i).setConstant(std::numeric_limits<double>::infinity());
        out.col(i).setConstant(std::numeric_limits<double>::infinity());
      }
  return out;
}

/// m, h / L, I / L^2: the body's parameters on one scale.
Vector10d lengthScale(double length) {
  Vector10d s;
  s << 1.0, length, length, length, length * length, length * length, length * length,
      length * length, length * length, length * length;
  return s;
}

/// A homogeneous sphere of density `density` with the estimate's mass (at least 1 g) at its centre
/// of mass (moved to within 1 m of the origin).
Vector10d uninformativePrior(const Vector10d& estimate, double density) {
  const double m = std::max(estimate[0], 1e-3);
  const double radius = std::cbrt(3.0 * m / (4.0 * M_PI * density));
  Eigen::Vector3d c = estimate[0] > 0.0 ? Eigen::Vector3d(estimate.segment<3>(1) / estimate[0])
                                        : Eigen::Vector3d::Zero();
  if (!c.allFinite()) c.setZero();
  if (c.norm() > 1.0) c /= c.norm();
  RigidInertia<double> sphere;
  sphere.mass = m;
  sphere.first_moment = m * c;
  const Eigen::Matrix3d sc = skew(c);
  sphere.inertia = Eigen::Matrix3d::Identity() * (0.4 * m * radius * radius) - m * sc * sc;
  return toStandardVector(sphere);
}

}  // namespace

PayloadFit fitPayload(const PayloadRows& rows, const PayloadFitOptions& options) {
  const int n = rows.numJoints(), f = rows.numExtra(), d = f + 10;
  if (rows.rows() < d + 1)
    throw InputError("the payload problem has " + std::to_string(rows.rows()) +
                     " torque rows for " + std::to_string(d) + " unknowns");
  if (!(options.length > 0.0)) throw InputError("the payload length scale must be > 0");
  if (!(options.prior_density > 0.0) || !std::isfinite(options.prior_density))
    throw InputError("the payload prior's density must be finite and > 0");
  const Eigen::MatrixXd X = rows.design();
  const Eigen::VectorXd y = rows.target();
  PayloadFit out;
  out.target_rms = jointRms(y, n);
  if (!(out.target_rms.maxCoeff() > 0.0))
    throw InputError("the payload's torques are zero on every joint: nothing to identify");

  // 1. The per-joint noise: from the unweighted fit, then again from the weighted one (a noisy
  // joint's share of the unweighted fit's error would otherwise inflate a quiet joint's noise).
  out.noise = jointNoise(y - X * scaledSolve(X, y), n, d, out.target_rms);
  Eigen::MatrixXd M(X.rows(), d + 1);
  const auto whiten = [&] {
    M.leftCols(d) = X;
    M.col(d) = y;
    for (Eigen::Index r = 0; r < M.rows(); ++r) M.row(r) /= out.noise[r % n];
  };
  whiten();
  {
    const Eigen::VectorXd x = scaledSolve(M.leftCols(d), M.col(d));
    out.noise = jointNoise(y - X * x, n, d, out.target_rms);
  }
  // 2. Whitened rows; QR of [extra | body | target].
  whiten();
  const Eigen::MatrixXd aw = M.leftCols(d);
  const Eigen::VectorXd yw = M.col(d);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(d + 1).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_ff = R.topLeftCorner(f, f), r_fp = R.block(0, f, f, 10);
  const Eigen::MatrixXd r_pp = R.block(f, f, 10, 10);
  const Eigen::VectorXd b_f = R.col(d).head(f), b_p = R.col(d).segment(f, 10);
  for (int k = 0; k < f; ++k)
    if (!(std::abs(r_ff(k, k)) > 1e-10 * std::max(r_ff.cwiseAbs().maxCoeff(), 1e-300)))
      throw InputError("extra column " + std::to_string(k + 1) +
                       " of the payload problem is not excited by the data");

  // 3. Least squares on the body block (the extra columns eliminated), minimum norm in scaled
  // units; the singular values of the same.
  const Vector10d scale = lengthScale(options.length);
  const Eigen::MatrixXd scaled = r_pp * scale.asDiagonal();
  const SquareSvd svd(scaled, Eigen::ComputeFullU | Eigen::ComputeFullV);
  out.singular_values = svd.singularValues();
  const double top = std::max(out.singular_values[0], 1e-300);
  std::vector<int> null;
  for (int k = 0; k < 10; ++k)
    if (out.singular_values[k] <= 1e-8 * top) null.push_back(k);
  out.null_directions.resize(10, static_cast<Eigen::Index>(null.size()));
  for (std::size_t i = 0; i < null.size(); ++i)
    out.null_directions.col(static_cast<Eigen::Index>(i)) =
        scale.asDiagonal() * svd.matrixV().col(null[i]);
  out.least_squares = scale.asDiagonal() * minimumNorm(svd, b_p, 1e-8);
  const auto extraAt = [&](const Vector10d& body) -> Eigen::VectorXd {
    if (f == 0) return Eigen::VectorXd();
    return r_ff.triangularView<Eigen::Upper>().solve(b_f - r_fp * body);
  };
  out.extra_least_squares = extraAt(out.least_squares);
  out.least_squares_consistent =
      checkPhysicalConsistency(fromStandardVector(out.least_squares), 0, "payload").empty() &&
      out.least_squares[0] > 0.0;

  // 4. Physically consistent: the entropic estimator on the one body.
  const ParameterLayout layout{1, DriveTerms::none()};
  out.prior =
      options.prior ? *options.prior : uninformativePrior(out.least_squares, options.prior_density);
  const PhysicalProblem problem =
      makePhysicalProblem(layout, r_pp, b_p, out.prior, options.prior_weight);
  Vector10d start = nearestConsistent(out.least_squares, 1e-8);
  if (!std::isfinite(problem.cost(start))) start = problem.prior;
  PhysicalOptions physical;
  physical.prior_weight = options.prior_weight;
  const PhysicalSolution solution = solvePhysicalProblem(problem, start, physical);
  out.theta = solution.theta;
  out.converged = solution.converged;
  out.termination = solution.termination;
  out.extra = extraAt(out.theta);

  // 5. Residuals and the covariance of the least-squares estimate.
  Eigen::VectorXd at(d), at_ls(d);
  at << out.extra, out.theta;
  at_ls << out.extra_least_squares, out.least_squares;
  out.residual_rms = jointRms(y - X * at, n);
  const Eigen::VectorXd ew = yw - aw * at_ls;
  out.batch = options.batch;
  out.covariance = sandwichCovariance(aw, ew, n, out.batch);
  return out;
}

GainFit fitDriveGains(const PayloadRows& rows, double mass,
                      const std::optional<Eigen::Vector3d>& com, int batch,
                      const Eigen::VectorXd& arm_difference) {
  const int n = rows.numJoints(), f = rows.numExtra();
  if (!(mass > 0.0) || !std::isfinite(mass))
    throw InputError("the known payload mass must be finite and > 0");
  if (com && !com->allFinite()) throw InputError("the known centre of mass must be finite");
  std::vector<int> free;  // body parameters fitted
  for (int k = com ? 4 : 1; k < 10; ++k) free.push_back(k);
  const int nf = static_cast<int>(free.size()), u = n + nf;
  if (rows.rows() < u + 1)
    throw InputError("the gain problem has " + std::to_string(rows.rows()) + " torque rows for " +
                     std::to_string(u) + " unknowns");
  const Eigen::MatrixXd P = rows.design().rightCols(10);
  const Eigen::VectorXd y = rows.target();
  const Eigen::Index count = y.size();
  if (arm_difference.size() != 0 && arm_difference.size() != count)
    throw InputError("the arm's torque difference has " + std::to_string(arm_difference.size()) +
                     " rows, the gain problem " + std::to_string(count));
  const Eigen::VectorXd delta =
      arm_difference.size() == 0 ? Eigen::VectorXd::Zero(count) : arm_difference;
  GainFit out;
  out.target_rms = jointRms(y, n);
  if (!(out.target_rms.maxCoeff() > 0.0))
    throw InputError("the loaded and unloaded torques are equal on every joint: no load is seen");
  (void)f;

  Vector10d theta = Vector10d::Zero();
  theta[0] = mass;
  if (com) theta.segment<3>(1) = mass * *com;
  Eigen::VectorXd g = Eigen::VectorXd::Ones(n);
  // Start: g = 1 (nominal constants), the free parameters by linear least squares.
  {
    Eigen::MatrixXd A(count, nf);
    for (int i = 0; i < nf; ++i) A.col(i) = P.col(free[i]);
    Eigen::VectorXd rhs = y;
    for (int k = 0; k < 10; ++k)
      if (std::find(free.begin(), free.end(), k) == free.end()) rhs -= P.col(k) * theta[k];
    const Eigen::VectorXd x = scaledSolve(A, rhs);
    for (int i = 0; i < nf; ++i) theta[free[i]] = x[i];
  }
  // The measured difference y + delta against g (delta + P theta); at g = 1 that is y - P theta.
  const auto residualOf = [&](const Eigen::VectorXd& gains, const Vector10d& body) {
    Eigen::VectorXd r = P * body + delta;
    for (Eigen::Index row = 0; row < count; ++row)
      r[row] = y[row] + delta[row] - gains[row % n] * r[row];
    return r;
  };
  Eigen::VectorXd residual = residualOf(g, theta);
  out.noise = jointNoise(residual, n, u, out.target_rms);
  Eigen::MatrixXd J(count, u);
  const auto jacobian = [&] {
    J.setZero();
    const Eigen::VectorXd body = P * theta + delta;
    for (Eigen::Index row = 0; row < count; ++row) {
      const int j = static_cast<int>(row % n);
      const double w = 1.0 / out.noise[j];
      J(row, j) = w * body[row];
      for (int i = 0; i < nf; ++i) J(row, n + i) = w * g[j] * P(row, free[i]);
    }
  };
  const auto whitened = [&](const Eigen::VectorXd& r) {
    Eigen::VectorXd w(count);
    for (Eigen::Index row = 0; row < count; ++row) w[row] = r[row] / out.noise[row % n];
    return w;
  };
  double cost = whitened(residual).squaredNorm();
  for (out.iterations = 0; out.iterations < 100; ++out.iterations) {
    jacobian();
    const Eigen::VectorXd step = scaledSolve(J, whitened(residual));
    double t = 1.0;
    Eigen::VectorXd g_try;
    Vector10d theta_try;
    double trial = cost;
    for (; t > 1e-6; t *= 0.5) {
      g_try = g + t * step.head(n);
      theta_try = theta;
      for (int i = 0; i < nf; ++i) theta_try[free[i]] += t * step[n + i];
      trial = whitened(residualOf(g_try, theta_try)).squaredNorm();
      if (trial <= cost) break;
    }
    if (!(trial <= cost)) break;
    const bool small = cost - trial <= 1e-14 * cost;
    g = g_try;
    theta = theta_try;
    residual = residualOf(g, theta);
    cost = trial;
    if (small) break;
  }
  jacobian();
  const Eigen::VectorXd ew = whitened(residual);
  out.batch = batch;
  out.covariance = sandwichCovariance(J, ew, n, out.batch);
  out.theta = theta;
  out.scale = g.cwiseInverse();
  out.scale_std.resize(n);
  for (int j = 0; j < n; ++j) out.scale_std[j] = std::sqrt(out.covariance(j, j)) / (g[j] * g[j]);
  out.residual_rms = jointRms(residual, n);
  return out;
}

}  // namespace dynid
