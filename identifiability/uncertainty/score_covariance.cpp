#include "identifiability/uncertainty/score_covariance.hpp"

#include <algorithm>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/errors.hpp"

namespace dynid {

ScoreCovariance::ScoreCovariance(Eigen::Index num_unknowns, int num_joints,
                                 long long expected_samples, int batch)
    : d_(num_unknowns), n_(num_joints) {
  if (num_unknowns < 1 || num_joints < 1)
    throw InputError("a score covariance needs at least one unknown and one joint");
  if (batch < 0) throw InputError("the covariance's `batch` must be >= 0 (0: from the residuals)");
  if (batch > 0) {
    storage_ = batch;
    fixed_ = true;
  } else {
    while (storage_ * kMaxScoreBatches < expected_samples) storage_ *= 2;
  }
  ring_ = Eigen::MatrixXd::Zero(n_, kMaxScoreLag);
  energy_ = Eigen::VectorXd::Zero(n_);
  for (Eigen::VectorXd& l : lagged_) l = Eigen::VectorXd::Zero(n_);
}

void ScoreCovariance::lag(const Eigen::Ref<const Eigen::VectorXd>& residual) {
  for (int i = 0; i < kLags; ++i) {
    const long long lag = 1LL << i;
    if (samples_ < lag) break;
    lagged_[static_cast<std::size_t>(i)] += residual.cwiseProduct(
        ring_.col(static_cast<Eigen::Index>((samples_ - lag) % kMaxScoreLag)));
  }
  energy_ += residual.cwiseAbs2();
  ring_.col(static_cast<Eigen::Index>(samples_ % kMaxScoreLag)) = residual;
  ++samples_;
}

void ScoreCovariance::add(const Eigen::Ref<const Eigen::MatrixXd>& rows,
                          const Eigen::Ref<const Eigen::VectorXd>& residual) {
  if (rows.rows() != n_ || rows.cols() != d_ || residual.size() != n_)
    throw InputError("a sample of " + std::to_string(rows.rows()) + " x " +
                     std::to_string(rows.cols()) + " rows and " + std::to_string(residual.size()) +
                     " residuals, expected " + std::to_string(n_) + " x " + std::to_string(d_) +
                     " and " + std::to_string(n_));
  if (samples_ % storage_ == 0)
    stored_.push_back({Eigen::VectorXd::Zero(d_), Eigen::MatrixXd::Zero(d_, d_)});
  Batch& batch = stored_.back();
  batch.score.noalias() += rows.transpose() * residual;
  batch.normal.selfadjointView<Eigen::Lower>().rankUpdate(rows.transpose());
  lag(residual);
}

ScoreCovariance::Block ScoreCovariance::prepare(
    const Eigen::Ref<const Eigen::MatrixXd>& rows,
    const Eigen::Ref<const Eigen::MatrixXd>& residuals) {
  Block out;
  const Eigen::Index n = residuals.rows();
  out.score = Eigen::VectorXd::Zero(rows.cols());
  for (Eigen::Index k = 0; k < residuals.cols(); ++k)
    out.score.noalias() += rows.middleRows(k * n, n).transpose() * residuals.col(k);
  out.normal = Eigen::MatrixXd::Zero(rows.cols(), rows.cols());
  out.normal.selfadjointView<Eigen::Lower>().rankUpdate(rows.transpose());
  out.residuals = residuals;
  return out;
}

void ScoreCovariance::add(const Block& block) {
  const auto m = static_cast<long long>(block.residuals.cols());
  if (block.score.size() != d_ || block.normal.rows() != d_ || block.residuals.rows() != n_)
    throw InputError("a block of the wrong size for this covariance");
  if (m == 0) return;
  if (samples_ / storage_ != (samples_ + m - 1) / storage_)
    throw InputError("a block of samples " + std::to_string(samples_) + " to " +
                     std::to_string(samples_ + m - 1) + " crosses a stored batch's end");
  if (samples_ % storage_ == 0)
    stored_.push_back({Eigen::VectorXd::Zero(d_), Eigen::MatrixXd::Zero(d_, d_)});
  stored_.back().score += block.score;
  stored_.back().normal += block.normal;
  for (long long k = 0; k < m; ++k) lag(block.residuals.col(static_cast<Eigen::Index>(k)));
}

std::vector<double> ScoreCovariance::autocorrelation() const {
  std::vector<double> out;
  for (int i = 0; i < kLags; ++i) {
    const long long lag = 1LL << i;
    if (30 * lag > samples_) break;
    double mean = 0.0;
    int joints = 0;
    for (int j = 0; j < n_; ++j) {
      if (!(energy_[j] > 0.0)) continue;
      mean += lagged_[static_cast<std::size_t>(i)][j] / energy_[j];
      ++joints;
    }
    out.push_back(joints > 0 ? mean / joints : 0.0);
  }
  return out;
}

int ScoreCovariance::batch() const {
  if (fixed_) return static_cast<int>(storage_);
  // The longest batch: a power of two, at most a thirtieth of the samples (never below storage).
  long long longest = 1;
  while (2 * longest <= samples_ / 30) longest *= 2;
  long long wanted = longest;
  const std::vector<double> rho = autocorrelation();
  for (std::size_t i = 0; i < rho.size(); ++i)
    if (rho[i] < kScoreIndependence) {
      wanted = std::min(i == 0 ? 1LL : 4LL << i, longest);
      break;
    }
  return static_cast<int>(std::max(wanted, storage_));
}

std::vector<ScoreCovariance::Batch> ScoreCovariance::joined(long long length) const {
  const long long group = std::max(1LL, length / storage_);
  std::vector<Batch> out;
  for (std::size_t i = 0; i < stored_.size(); ++i) {
    if (i % static_cast<std::size_t>(group) == 0)
      out.push_back({Eigen::VectorXd::Zero(d_), Eigen::MatrixXd::Zero(d_, d_)});
    out.back().score += stored_[i].score;
    out.back().normal += stored_[i].normal;
  }
  for (Batch& b : out) b.normal = b.normal.selfadjointView<Eigen::Lower>();
  return out;
}

Eigen::MatrixXd ScoreCovariance::normal() const {
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(d_, d_);
  for (const Batch& b : stored_) h += b.normal;
  return h.selfadjointView<Eigen::Lower>();
}

Eigen::MatrixXd ScoreCovariance::meat() const {
  const double rows = static_cast<double>(samples_) * n_;
  const double factor = rows / std::max(rows - static_cast<double>(d_), 1.0);
  Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(d_, d_);
  for (const Batch& b : joined(batch())) omega.selfadjointView<Eigen::Lower>().rankUpdate(b.score);
  return factor * Eigen::MatrixXd(omega.selfadjointView<Eigen::Lower>());
}

Eigen::MatrixXd ScoreCovariance::covariance() const {
  return robustCovariance(normal(), joined(batch()));
}

Eigen::MatrixXd robustCovariance(const Eigen::MatrixXd& h, const std::vector<ScoreBatch>& batches) {
  // In unit-diagonal scaling (parameters of very different magnitudes), scaled back at the end:
  // with H = L L^T and G_b = L^-1 H_b L^-T (eigenvalues in [0, 1): batch b's leverage),
  // H^-1 (I - H_b H^-1)^-1/2 s_b = L^-T (I - G_b)^-1/2 L^-1 s_b.
  const Eigen::Index d = h.rows();
  Eigen::VectorXd scale = h.diagonal().cwiseSqrt();
  for (Eigen::Index i = 0; i < d; ++i) scale[i] = scale[i] > 0.0 ? 1.0 / scale[i] : 1.0;
  const Eigen::LLT<Eigen::MatrixXd> whole(scale.asDiagonal() * h * scale.asDiagonal());
  if (whole.info() != Eigen::Success)
    throw NumericalError("the covariance's normal matrix is not positive definite");
  const Eigen::MatrixXd l = whole.matrixL();
  const auto lower = l.triangularView<Eigen::Lower>();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(d, d);
  for (const ScoreBatch& b : batches) {
    Eigen::MatrixXd g = scale.asDiagonal() * b.normal * scale.asDiagonal();
    lower.solveInPlace(g);                                   // L^-1 H_b
    g = lower.solve(Eigen::MatrixXd(g.transpose())).eval();  // L^-1 H_b L^-T (symmetric)
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (g + g.transpose()));
    // A direction only this batch sees (leverage 1) is capped at a thousandfold weight.
    const Eigen::VectorXd weight =
        (1.0 - eigen.eigenvalues().array().min(1.0 - 1e-6).max(0.0)).rsqrt().matrix();
    Eigen::VectorXd u = lower.solve(scale.cwiseProduct(b.score));
    u = eigen.eigenvectors() * weight.cwiseProduct(eigen.eigenvectors().transpose() * u);
    const Eigen::VectorXd step =
        scale.cwiseProduct(l.transpose().triangularView<Eigen::Upper>().solve(u));
    out.selfadjointView<Eigen::Lower>().rankUpdate(step);
  }
  return out.selfadjointView<Eigen::Lower>();
}

}  // namespace dynid
