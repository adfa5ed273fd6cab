#include "identifiability/least_squares_stream.hpp"

#include "identifiability/tall_qr.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

namespace {

/// The samples are dealt to kLanes lanes in blocks of kLaneRows: global block g (samples
/// g kLaneRows to (g + 1) kLaneRows - 1) goes to lane g mod kLanes. Each lane has its own factor
/// per joint, reduced once per block (TallQr's block_rows), so a thread computes a block's
/// regressors and folds them into its lane's factors while the rows are still in its cache, and
/// no two threads write the same memory. Fixed numbers, not the thread count: the result is the
/// same bits for any thread count and any chunking. The lanes' factors are stacked at the end
/// (a tall QR of kLanes small triangles per joint).
constexpr int kLanes = 8;
constexpr Eigen::Index kLaneRows = 128;

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
  out.condition_number = conditionNumber(scaled);
  out.condition_number_unscaled = conditionNumber(r);
  return out;
}

}  // namespace

LeastSquaresStream::LeastSquaresStream(LeastSquaresStream&&) noexcept = default;
LeastSquaresStream::~LeastSquaresStream() = default;

LeastSquaresStream::LeastSquaresStream(const BaseParameters& base, int num_joints)
    : base_(base), n_(num_joints), b_(base.numBase()) {
  if (num_joints < 1) throw InputError("least squares needs at least one joint");
  std::vector<int> all(static_cast<std::size_t>(b_));
  for (int c = 0; c < b_; ++c) all[static_cast<std::size_t>(c)] = c;
  support_.assign(static_cast<std::size_t>(n_), all);
  zeros_.assign(static_cast<std::size_t>(n_), {});
  lanes_.assign(kLanes, {});
  for (std::vector<TallQr>& lane : lanes_) {
    lane.reserve(static_cast<std::size_t>(n_));
    for (int j = 0; j < n_; ++j) lane.emplace_back(b_ + 1, kLaneRows);
  }
  tau_squared_ = Eigen::VectorXd::Zero(n_);
  left_out_.assign(kLanes, std::vector<long long>(static_cast<std::size_t>(n_), 0));
  row_.resize(b_ + 1);
}

Eigen::VectorXd LeastSquaresStream::fittedRows() const {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(n_, static_cast<double>(samples_));
  for (const std::vector<long long>& lane : left_out_)
    for (int j = 0; j < n_; ++j) out[j] -= static_cast<double>(lane[static_cast<std::size_t>(j)]);
  if (given_left_out_.size() == n_) out -= given_left_out_;
  return out;
}

JointSupport jointSupport(const BaseParameters& base, const Model& model) {
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
  JointSupport out;
  const int n = model.numJoints();
  out.support.resize(static_cast<std::size_t>(n));
  out.zeros.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < base.numBase(); ++c)
      if (acts(base.independent[static_cast<std::size_t>(c)], j))
        out.support[static_cast<std::size_t>(j)].push_back(c);
    for (int s = 0; s < layout.size(); ++s)
      if (!acts(s, j)) out.zeros[static_cast<std::size_t>(j)].push_back(s);
  }
  return out;
}

LeastSquaresStream::LeastSquaresStream(const BaseParameters& base, const Model& model)
    : LeastSquaresStream(base, model.numJoints()) {
  JointSupport supports = jointSupport(base, model);
  support_ = std::move(supports.support);
  zeros_ = std::move(supports.zeros);
  for (std::vector<TallQr>& lane : lanes_) {
    lane.clear();
    for (int j = 0; j < n_; ++j)
      lane.emplace_back(static_cast<Eigen::Index>(support_[static_cast<std::size_t>(j)].size()) + 1,
                        kLaneRows);
  }
}

void LeastSquaresStream::addFactors(const std::vector<Eigen::MatrixXd>& joint_factors,
                                    long long samples, const Eigen::VectorXd& fitted_rows,
                                    const Eigen::VectorXd& tau_squared, double max_abs_tau) {
  if (static_cast<int>(joint_factors.size()) != n_ || fitted_rows.size() != n_ ||
      tau_squared.size() != n_)
    throw InputError("factors of " + std::to_string(joint_factors.size()) + " joints for a " +
                     std::to_string(n_) + "-joint least-squares stream");
  for (int j = 0; j < n_; ++j) {
    const auto cols = static_cast<Eigen::Index>(support_[static_cast<std::size_t>(j)].size()) + 1;
    const Eigen::MatrixXd& r = joint_factors[static_cast<std::size_t>(j)];
    if (r.cols() != cols || !r.allFinite())
      throw InputError("joint " + std::to_string(j + 1) + "'s factor has " +
                       std::to_string(r.cols()) + " columns, its support " + std::to_string(cols));
  }
  if (samples < 0 || !fitted_rows.allFinite() || !tau_squared.allFinite() ||
      !std::isfinite(max_abs_tau) || samples + samples_ > std::numeric_limits<int>::max())
    throw InputError("factors of " + std::to_string(samples) + " samples with totals that are not");
  if (given_.empty()) {
    given_.assign(static_cast<std::size_t>(n_), {});
    given_left_out_ = Eigen::VectorXd::Zero(n_);
  }
  for (int j = 0; j < n_; ++j) {
    Eigen::MatrixXd& mine = given_[static_cast<std::size_t>(j)];
    const Eigen::MatrixXd& r = joint_factors[static_cast<std::size_t>(j)];
    TallQr stacked(r.cols(), mine.rows() + r.rows());
    if (mine.size() > 0) stacked.add(mine);
    stacked.add(r);
    mine = stacked.r();
  }
  given_left_out_ += Eigen::VectorXd::Constant(n_, static_cast<double>(samples)) - fitted_rows;
  tau_squared_ += tau_squared;
  max_abs_tau_ = std::max(max_abs_tau_, max_abs_tau);
  samples_ += static_cast<int>(samples);
  factored_samples_ = -1;  // jointFactor's cache is stale
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
  std::vector<TallQr>& lane = lanes_[static_cast<std::size_t>((samples_ / kLaneRows) % kLanes)];
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
    lane[static_cast<std::size_t>(j)].addRow(row_.head(p + 1));
  }
  addTau(tau);
  ++samples_;
  if (samples_ % kLaneRows == 0)  // the block's end, as in addTrajectory
    for (TallQr& factor : lane) factor.flush();
}

void LeastSquaresStream::checkSizes(const Model& model, const Trajectory& data) const {
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
}

std::vector<std::vector<Eigen::Index>> regressorOffsets(
    const std::vector<std::vector<int>>& columns, int num_joints,
    const std::vector<int>* standard) {
  std::vector<std::vector<Eigen::Index>> out(columns.size());
  for (std::size_t j = 0; j < columns.size(); ++j)
    for (int c : columns[j]) {
      const int column = standard ? (*standard)[static_cast<std::size_t>(c)] : c;
      out[j].push_back(static_cast<Eigen::Index>(column) * num_joints +
                       static_cast<Eigen::Index>(j));
    }
  return out;
}

void LeastSquaresStream::makeGather() {
  gather_ = regressorOffsets(support_, n_, &base_.independent);
  zero_offsets_ = regressorOffsets(zeros_, n_);
}

void LeastSquaresStream::addTaus(const Trajectory& data, long long first, const FitRows* rows) {
  if (!rows) {
    for (int k = 0; k < data.numSamples(); ++k) addTau(data.tau.col(k));
    return;
  }
  Eigen::VectorXd tau(n_);
  for (int k = 0; k < data.numSamples(); ++k) {
    for (int j = 0; j < n_; ++j)
      tau[j] = rows->fitted(first + k, j, data.dq(j, k)) ? data.tau(j, k) : 0.0;
    addTau(tau);
  }
}

void LeastSquaresStream::addTrajectory(const Model& model, const Trajectory& data, ThreadPool* pool,
                                       const FitRows* rows) {
  checkSizes(model, data);
  const int m = data.numSamples();
  checkFiniteSamples(data);
  if (m == 0) return;
  if (gather_.empty()) makeGather();
  const int threads = pool ? pool->numThreads() : 1;
  // Each thread's workspace (a Data) is made on that thread, the first time it runs (below):
  // memory a thread writes then comes from its own allocator arena, never sharing a cache line
  // with another thread's.
  if (static_cast<int>(workspaces_.size()) < threads)
    workspaces_.resize(static_cast<std::size_t>(threads));
  const long long first = samples_;  // the chunk's samples are first .. first + m - 1
  const long long first_block = first / kLaneRows, last_block = (first + m - 1) / kLaneRows;
  std::atomic<int> structure_error{-1};  // the joint whose zero columns were not zero
  std::atomic<bool> out_of_step{false};  // a lane's buffer without room for its block (a bug)
  // One lane: its blocks in this chunk in order, each block's regressor rows written straight
  // into the lane's factors' buffers (a block fits: both are kLaneRows long and aligned), then
  // reduced there.
  const auto lane_work = [&](int lane, int thread) {
    std::unique_ptr<Data>& own = workspaces_[static_cast<std::size_t>(thread)];
    if (!own) own = std::make_unique<Data>(model);
    std::vector<TallQr>& factors = lanes_[static_cast<std::size_t>(lane)];
    std::vector<long long>& left_out = left_out_[static_cast<std::size_t>(lane)];
    Eigen::MatrixXd adjusted;  // with `rows`: the sample's regressor as the fit takes it
    Eigen::VectorXd tau;
    long long block = first_block + ((lane - first_block % kLanes) + kLanes) % kLanes;
    for (; block <= last_block; block += kLanes) {
      const auto begin = static_cast<int>(std::max(first, block * kLaneRows) - first);
      const auto end = static_cast<int>(std::min(first + m, (block + 1) * kLaneRows) - first);
      for (const TallQr& factor : factors)  // the block's earlier rows are all its buffer holds
        if (factor.room() < end - begin) {
          out_of_step.store(true);
          return;
        }
      for (int k = begin; k < end; ++k) {
        const Eigen::MatrixXd& regressor =
            jointTorqueRegressor(model, *own, data.q.col(k), data.dq.col(k), data.ddq.col(k));
        const double* y = regressor.data();
        const double* measured = &data.tau(0, k);
        if (rows) {
          adjusted = regressor;
          tau = data.tau.col(k);
          rows->apply(first + k, data.dq.col(k), adjusted, tau);
          for (int j = 0; j < n_; ++j)
            if (!rows->fitted(first + k, j, data.dq(j, k))) ++left_out[static_cast<std::size_t>(j)];
          y = adjusted.data();
          measured = tau.data();
        }
        // The chain's structure is the model's, not the sample's: checked on each block's first
        // sample, it costs nothing per sample.
        const bool check = k == begin;
        for (int j = 0; j < n_; ++j) {
          const auto jj = static_cast<std::size_t>(j);
          if (check)
            for (Eigen::Index offset : zero_offsets_[jj])
              if (y[offset] != 0.0) structure_error.store(j);
          TallQr& factor = factors[jj];
          double* row = factor.freeRows() + (k - begin) * factor.rowStride();
          const std::vector<Eigen::Index>& gather = gather_[jj];
          const std::size_t p = gather.size();
          for (std::size_t c = 0; c < p; ++c) row[c] = y[gather[c]];
          row[p] = measured[j];
        }
      }
      // At a block's end its rows are reduced, also when an estimate in the middle of the block
      // already reduced its first rows: each lane's buffer then starts the next block empty.
      const bool block_ends = first + end == (block + 1) * kLaneRows;
      for (TallQr& factor : factors) {
        factor.commitRows(end - begin);
        if (block_ends) factor.flush();
      }
    }
  };
  if (pool)
    pool->parallelFor(kLanes, lane_work);
  else
    for (int lane = 0; lane < kLanes; ++lane) lane_work(lane, 0);
  if (out_of_step.load()) throw Error("LeastSquaresStream: a lane's factor is out of step");
  if (structure_error.load() >= 0)
    throw Error("the regressor acts on joint " + std::to_string(structure_error.load() + 1) +
                " through a parameter the model's chain says cannot act on it");
  addTaus(data, first, rows);
  samples_ += m;
}

const Eigen::MatrixXd& LeastSquaresStream::jointFactor(int j) {
  if (factored_samples_ != samples_) {  // -1 before the first call
    joint_factors_.assign(static_cast<std::size_t>(n_), {});
    for (int i = 0; i < n_; ++i) {
      const Eigen::Index cols = lanes_.front()[static_cast<std::size_t>(i)].cols();
      TallQr stacked(cols, (kLanes + 1) * cols);
      for (std::vector<TallQr>& lane : lanes_) stacked.add(lane[static_cast<std::size_t>(i)].r());
      if (!given_.empty()) stacked.add(given_[static_cast<std::size_t>(i)]);
      joint_factors_[static_cast<std::size_t>(i)] = stacked.r();
    }
    factored_samples_ = samples_;
  }
  return joint_factors_[static_cast<std::size_t>(j)];
}

Eigen::MatrixXd LeastSquaresStream::scattered(int j) {
  const std::vector<int>& support = support_[static_cast<std::size_t>(j)];
  const Eigen::MatrixXd& r = jointFactor(j);
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

Eigen::MatrixXd LeastSquaresStream::augmentedFactor() {
  return combined(Eigen::VectorXd::Ones(n_));
}

Eigen::VectorXd LeastSquaresStream::residualSquares(const Eigen::VectorXd& beta) {
  if (beta.size() != b_)
    throw InputError("residualSquares: beta has " + std::to_string(beta.size()) + " entries, " +
                     std::to_string(b_) + " base parameters");
  // |tau_j - W1_j beta|^2 = |R_j [-beta; 1]|^2 for joint j's augmented factor R_j.
  Eigen::VectorXd x(b_ + 1);
  x.head(b_) = -beta;
  x[b_] = 1.0;
  Eigen::VectorXd out(n_);
  for (int j = 0; j < n_; ++j) out[j] = (scattered(j) * x).squaredNorm();
  return out;
}

LeastSquaresStream::Factor LeastSquaresStream::factor() {
  const Eigen::MatrixXd r = augmentedFactor().topLeftCorner(b_, b_);
  Factor out;
  out.norms = r.colwise().norm().transpose();
  Eigen::VectorXd safe = out.norms;
  for (Eigen::Index j = 0; j < b_; ++j)
    if (safe[j] == 0.0) safe[j] = 1.0;
  out.r_scaled = r * safe.cwiseInverse().asDiagonal();
  return out;
}

BaseEstimate LeastSquaresStream::estimate(LeastSquaresMethod method) {
  const Eigen::VectorXd fitted = fittedRows();
  const double rows = fitted.sum();
  if (rows < b_)
    throw InputError(
        "the data has " + std::to_string(static_cast<long long>(rows)) + " torque rows" +
        (rows < static_cast<double>(samples_) * n_ ? " fitted (a joint at rest is not)" : "") +
        ", fewer than the " + std::to_string(b_) + " base parameters");
  // OLS first: its factor measures the excitation, its residuals give the per-joint noise (WLS).
  const Eigen::MatrixXd ols_factor = augmentedFactor();
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
  BaseEstimate out;
  out.method = method;
  out.num_samples = samples_;
  out.fitted_rows = fitted;
  const Eigen::VectorXd ols_squared = residualSquares(ols.beta);
  const Eigen::VectorXd dof_per_joint =
      (fitted.array() - static_cast<double>(b_) / n_).cwiseMax(1.0).matrix();
  out.joint_sigma = ols_squared.cwiseQuotient(dof_per_joint).cwiseSqrt();
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
    chosen_squared = residualSquares(chosen.beta);
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
  const Eigen::VectorXd per_joint = fitted.cwiseMax(1.0);  // a joint never fitted: 0, not NaN
  out.residual_rms = chosen_squared.cwiseQuotient(per_joint).cwiseSqrt();
  out.measured_rms = tau_squared_.cwiseQuotient(per_joint).cwiseSqrt();
  setRelativeErrors(out);
  return out;
}

void addTrajectory(LeastSquaresStream& stream, const Model& model, const Trajectory& data,
                   ThreadPool* pool) {
  stream.addTrajectory(model, data, pool);
}

}  // namespace dynid
