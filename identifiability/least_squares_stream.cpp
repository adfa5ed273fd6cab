#include "identifiability/least_squares_stream.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <Eigen/SVD>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

namespace {

/// TallQr's buffered rows per joint: large enough to amortise each reduction.
constexpr Eigen::Index kBlockRows = 1024;

double conditionOf(const Eigen::MatrixXd& r) {
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(r).singularValues();
  return s.size() == 0 || s[s.size() - 1] == 0.0 ? std::numeric_limits<double>::infinity()
                                                 : s[0] / s[s.size() - 1];
}

/// Everything a BaseEstimate takes from the (weighted) system's augmented factor [R | Q^T y].
struct Solved {
  Eigen::VectorXd beta;
  Eigen::MatrixXd covariance_unit;  // (A^T A)^-1 in physical units
  Eigen::VectorXd r_diagonal;       // |R_jj| of the column-scaled A; 0 for a zero column
  Eigen::VectorXd independence;
  double condition_number = 0.0, condition_number_unscaled = 0.0;
};

/// From R_aug ((b+1) x (b+1)): the column norms of A are those of R, so R D^-1 is the factor of
/// the column-scaled A, solved in scaled coordinates as the dense path does.
Solved solveFactor(const Eigen::MatrixXd& r_augmented, Eigen::Index b, bool need_inverse) {
  const Eigen::MatrixXd r = r_augmented.topLeftCorner(b, b);
  const Eigen::VectorXd squared = r.colwise().squaredNorm().transpose();
  Eigen::VectorXd norms = squared.cwiseSqrt();
  for (Eigen::Index j = 0; j < b; ++j)
    if (norms[j] == 0.0) norms[j] = 1.0;  // an unexcited column: R_jj = 0 says so
  const Eigen::MatrixXd scaled = r * norms.cwiseInverse().asDiagonal();
  Solved out;
  out.r_diagonal = scaled.diagonal().cwiseAbs();
  for (Eigen::Index j = 0; j < b; ++j)
    if (squared[j] == 0.0) out.r_diagonal[j] = 0.0;
  if (!need_inverse) return out;
  out.beta =
      scaled.triangularView<Eigen::Upper>().solve(r_augmented.col(b).head(b)).cwiseQuotient(norms);
  const Eigen::MatrixXd inverse =
      scaled.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
  // With unit columns, (As^T As)^-1 = R^-1 R^-T: its diagonal is the variance inflation factor.
  out.independence = inverse.rowwise().norm().cwiseInverse();
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  out.covariance_unit =
      inv_norms.asDiagonal() * (inverse * inverse.transpose()) * inv_norms.asDiagonal();
  out.condition_number = conditionOf(scaled);
  out.condition_number_unscaled = conditionOf(r);
  return out;
}

}  // namespace

LeastSquaresStream::LeastSquaresStream(const BaseParameters& base, int num_joints)
    : base_(base), n_(num_joints), b_(base.numBase()) {
  if (num_joints < 1) throw InputError("least squares needs at least one joint");
  std::vector<int> all(static_cast<std::size_t>(b_));
  for (int c = 0; c < b_; ++c) all[static_cast<std::size_t>(c)] = c;
  support_.assign(static_cast<std::size_t>(n_), all);
  zeros_.assign(static_cast<std::size_t>(n_), {});
  joints_.reserve(static_cast<std::size_t>(n_));
  for (int j = 0; j < n_; ++j) joints_.emplace_back(b_ + 1, kBlockRows);
  tau_squared_ = Eigen::VectorXd::Zero(n_);
  row_.resize(b_ + 1);
}

LeastSquaresStream::LeastSquaresStream(const BaseParameters& base, const Model& model)
    : LeastSquaresStream(base, model.numJoints()) {
  const ParameterLayout layout = model.parameterLayout();
  if (layout.size() != base.numStandard())
    throw InputError("base parameters of " + std::to_string(base.numStandard()) +
                     " standard parameters for model '" + model.name + "' with " +
                     std::to_string(layout.size()));
  // Whether standard column s can act on joint j: a link's inertial parameters act on the joints
  // that carry it (j an ancestor of the link, or the link's own), a drive term on its own joint.
  const auto acts = [&](int s, int j) {
    const int link = s / layout.perLink();
    if (s % layout.perLink() >= kLinkParameterCount) return link == j;
    for (int i = link; i >= 0; i = model.parents()[static_cast<std::size_t>(i)])
      if (i == j) return true;
    return false;
  };
  joints_.clear();
  for (int j = 0; j < n_; ++j) {
    std::vector<int>& support = support_[static_cast<std::size_t>(j)];
    support.clear();
    for (int c = 0; c < b_; ++c)
      if (acts(base.independent[static_cast<std::size_t>(c)], j)) support.push_back(c);
    for (int s = 0; s < layout.size(); ++s)
      if (!acts(s, j)) zeros_[static_cast<std::size_t>(j)].push_back(s);
    joints_.emplace_back(static_cast<Eigen::Index>(support.size()) + 1, kBlockRows);
  }
}

void LeastSquaresStream::addTau(const Eigen::Ref<const Eigen::VectorXd>& tau) {
  tau_squared_ += tau.cwiseAbs2();
  max_abs_tau_ = std::max(max_abs_tau_, tau.cwiseAbs().maxCoeff());
}

void LeastSquaresStream::add(const Eigen::Ref<const Eigen::MatrixXd>& Y,
                             const Eigen::Ref<const Eigen::VectorXd>& tau) {
  if (Y.rows() != n_ || Y.cols() != base_.numStandard() || tau.size() != n_)
    throw InputError("a sample of " + std::to_string(Y.rows()) + " x " + std::to_string(Y.cols()) +
                     " regressor and " + std::to_string(tau.size()) + " torques, expected " +
                     std::to_string(n_) + " x " + std::to_string(base_.numStandard()) + " and " +
                     std::to_string(n_));
  if (!Y.allFinite() || !tau.allFinite())
    throw InputError("sample " + std::to_string(samples_) + " has a value that is not finite");
  for (int j = 0; j < n_; ++j) {
    for (int s : zeros_[static_cast<std::size_t>(j)])
      if (Y(j, s) != 0.0)
        throw Error("the regressor acts on joint " + std::to_string(j + 1) + " through " +
                    base_.standard_names[static_cast<std::size_t>(s)] +
                    ", which the model's chain says cannot act on it");
    const std::vector<int>& support = support_[static_cast<std::size_t>(j)];
    const auto p = static_cast<Eigen::Index>(support.size());
    for (Eigen::Index c = 0; c < p; ++c)
      row_[c] = Y(j, base_.independent[static_cast<std::size_t>(support[c])]);
    row_[p] = tau[j];
    joints_[static_cast<std::size_t>(j)].addRow(row_.head(p + 1));
  }
  addTau(tau);
  ++samples_;
}

void LeastSquaresStream::addTrajectory(const Model& model, const Trajectory& data,
                                       ThreadPool* pool) {
  if (data.numJoints() != model.numJoints())
    throw InputError("the data has " + std::to_string(data.numJoints()) + " joints, model '" +
                     model.name + "' has " + std::to_string(model.numJoints()));
  if (n_ != model.numJoints())
    throw InputError("the least-squares stream has " + std::to_string(n_) + " joints, model '" +
                     model.name + "' has " + std::to_string(model.numJoints()));
  if (model.parameterLayout().size() != base_.numStandard())
    throw InputError(
        "model '" + model.name + "' has " + std::to_string(model.parameterLayout().size()) +
        " standard parameters, the base parameters are of " + std::to_string(base_.numStandard()));
  const int m = data.numSamples();
  for (int k = 0; k < m; ++k) checkFiniteSample(data, k);
  if (m == 0) return;
  if (gather_.empty()) {
    for (int j = 0; j < n_; ++j) {
      std::vector<Eigen::Index> gather, zeros;
      for (int c : support_[static_cast<std::size_t>(j)])
        gather.push_back(
            static_cast<Eigen::Index>(base_.independent[static_cast<std::size_t>(c)]) * n_ + j);
      for (int s : zeros_[static_cast<std::size_t>(j)])
        zeros.push_back(static_cast<Eigen::Index>(s) * n_ + j);
      gather_.push_back(std::move(gather));
      zero_offsets_.push_back(std::move(zeros));
    }
  }
  const int threads = pool ? pool->numThreads() : 1;
  // Each thread's workspace is made on that thread, the first time it runs (below): memory a
  // thread writes then comes from its own allocator arena, never sharing a cache line with another
  // thread's.
  if (static_cast<int>(workspaces_.size()) < threads)
    workspaces_.resize(static_cast<std::size_t>(threads));
  chunk_rows_.resize(static_cast<std::size_t>(n_));
  for (int j = 0; j < n_; ++j) {
    TallQr::RowMajorMatrix& rows = chunk_rows_[static_cast<std::size_t>(j)];
    const auto p = static_cast<Eigen::Index>(support_[static_cast<std::size_t>(j)].size());
    if (rows.rows() < m || rows.cols() != p + 1) rows.resize(m, p + 1);
  }
  // Regressors by blocks of samples (each block's rows: whole cache lines of one thread).
  constexpr int kBlock = 64;
  const int blocks = (m + kBlock - 1) / kBlock;
  std::atomic<int> structure_error{-1};  // the joint whose zero columns were not zero
  const auto regressors = [&](int block, int thread) {
    std::unique_ptr<Data>& own = workspaces_[static_cast<std::size_t>(thread)];
    if (!own) own = std::make_unique<Data>(model);
    Data& work = *own;
    for (int k = block * kBlock; k < std::min(m, (block + 1) * kBlock); ++k) {
      const double* y =
          jointTorqueRegressor(model, work, data.q.col(k), data.dq.col(k), data.ddq.col(k)).data();
      // The chain's structure is the model's, not the sample's: checked on each block's first
      // sample, it costs nothing per sample.
      const bool check = k == block * kBlock;
      for (int j = 0; j < n_; ++j) {
        const auto jj = static_cast<std::size_t>(j);
        if (check)
          for (Eigen::Index offset : zero_offsets_[jj])
            if (y[offset] != 0.0) structure_error.store(j);
        double* row = chunk_rows_[jj].row(k).data();  // row-major: one sample's row contiguous
        const std::vector<Eigen::Index>& gather = gather_[jj];
        const std::size_t p = gather.size();
        for (std::size_t c = 0; c < p; ++c) row[c] = y[gather[c]];
        row[p] = data.tau(j, k);
      }
    }
  };
  if (pool)
    pool->parallelFor(blocks, regressors);
  else
    for (int block = 0; block < blocks; ++block) regressors(block, 0);
  if (structure_error.load() >= 0)
    throw Error("the regressor acts on joint " + std::to_string(structure_error.load() + 1) +
                " through a parameter the model's chain says cannot act on it");
  // Each joint's factor on one thread, the widest first.
  const auto update = [&](int index, int) {
    const auto j = static_cast<std::size_t>(index);
    joints_[j].addRowMajor(chunk_rows_[j].topRows(m));
  };
  if (pool)
    pool->parallelFor(n_, update);
  else
    for (int j = 0; j < n_; ++j) update(j, 0);
  for (int k = 0; k < m; ++k) addTau(data.tau.col(k));
  samples_ += m;
}

Eigen::MatrixXd LeastSquaresStream::scattered(int j) {
  const std::vector<int>& support = support_[static_cast<std::size_t>(j)];
  const Eigen::MatrixXd r = joints_[static_cast<std::size_t>(j)].r();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(r.rows(), b_ + 1);
  for (std::size_t c = 0; c < support.size(); ++c)
    out.col(support[c]) = r.col(static_cast<Eigen::Index>(c));
  out.col(b_) = r.col(r.cols() - 1);
  return out;
}

Eigen::MatrixXd LeastSquaresStream::combined(const Eigen::VectorXd& weight) {
  TallQr all(b_ + 1, static_cast<Eigen::Index>(n_) * (b_ + 1));
  for (int j = 0; j < n_; ++j) all.add(weight[j] * scattered(j));
  return all.r();
}

LeastSquaresStream::Factor LeastSquaresStream::factor() {
  const Eigen::MatrixXd r = combined(Eigen::VectorXd::Ones(n_)).topLeftCorner(b_, b_);
  Factor out;
  out.norms = r.colwise().norm().transpose();
  Eigen::VectorXd safe = out.norms;
  for (Eigen::Index j = 0; j < b_; ++j)
    if (safe[j] == 0.0) safe[j] = 1.0;
  out.r_scaled = r * safe.cwiseInverse().asDiagonal();
  return out;
}

BaseEstimate LeastSquaresStream::estimate(LeastSquaresMethod method) {
  const double rows = static_cast<double>(samples_) * n_;
  if (rows < b_)
    throw InputError("the data has " + std::to_string(samples_ * n_) +
                     " torque rows, fewer than the " + std::to_string(b_) + " base parameters");
  // OLS first: its factor measures the excitation, its residuals give the per-joint noise (WLS).
  const Eigen::MatrixXd ols_factor = combined(Eigen::VectorXd::Ones(n_));
  Solved ols = solveFactor(ols_factor, b_, false);
  const Excitation excitation = excitationFromRDiagonal(ols.r_diagonal);
  if (!excitation.unexcited.empty()) {
    std::string names;
    for (int j : excitation.unexcited) names += (names.empty() ? "" : ", ") + base_.baseName(j);
    throw NumericalError("the data do not excite " + std::to_string(excitation.unexcited.size()) +
                         " of the " + std::to_string(b_) + " base parameters (" + names +
                         "): rank " + std::to_string(excitation.rank) + " < " + std::to_string(b_) +
                         "; refusing to solve a rank-deficient problem");
  }
  ols = solveFactor(ols_factor, b_, true);
  // |tau_j - W1_j beta|^2 = |R_j [-beta; 1]|^2 for joint j's augmented factor R_j.
  const auto residual_squared = [&](const Eigen::VectorXd& beta) {
    Eigen::VectorXd x(b_ + 1);
    x.head(b_) = -beta;
    x[b_] = 1.0;
    Eigen::VectorXd out(n_);
    for (int j = 0; j < n_; ++j) out[j] = (scattered(j) * x).squaredNorm();
    return out;
  };
  const double samples = static_cast<double>(samples_);
  BaseEstimate out;
  out.method = method;
  out.num_samples = samples_;
  const Eigen::VectorXd ols_squared = residual_squared(ols.beta);
  const double dof_per_joint = samples - static_cast<double>(b_) / n_;
  out.joint_sigma = (ols_squared / std::max(dof_per_joint, 1.0)).cwiseSqrt();
  Solved chosen;
  Eigen::VectorXd chosen_squared;
  if (method == LeastSquaresMethod::kOrdinary) {
    const double sigma2 = ols_squared.sum() / std::max(rows - b_, 1.0);
    chosen = std::move(ols);
    chosen_squared = ols_squared;
    out.covariance = sigma2 * chosen.covariance_unit;
  } else {
    // A joint whose residual vanishes (noise-free data) gets a floor, not an infinite weight.
    Eigen::VectorXd sigma = out.joint_sigma;
    const double floor = 1e-15 * (1.0 + max_abs_tau_);
    for (Eigen::Index j = 0; j < n_; ++j) sigma[j] = std::max(sigma[j], floor);
    chosen = solveFactor(combined(sigma.cwiseInverse()), b_, true);
    chosen_squared = residual_squared(chosen.beta);
    out.covariance = chosen.covariance_unit;
  }
  out.beta = chosen.beta;
  out.condition_number = chosen.condition_number;
  out.condition_number_unscaled = chosen.condition_number_unscaled;
  out.independence = chosen.independence;
  out.std_dev = out.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  out.relative_std_dev_percent.resize(b_);
  for (int j = 0; j < b_; ++j)
    out.relative_std_dev_percent[j] = out.beta[j] != 0.0
                                          ? 100.0 * out.std_dev[j] / std::abs(out.beta[j])
                                          : std::numeric_limits<double>::infinity();
  out.residual_rms = (chosen_squared / samples).cwiseSqrt();
  out.measured_rms = (tau_squared_ / samples).cwiseSqrt();
  setRelativeErrors(out);
  return out;
}

void addTrajectory(LeastSquaresStream& stream, const Model& model, const Trajectory& data,
                   ThreadPool* pool) {
  stream.addTrajectory(model, data, pool);
}

}  // namespace dynid
