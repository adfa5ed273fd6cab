#include "identifiability/least_squares_summary.hpp"

#include "identifiability/tall_qr.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

namespace {

LeastSquaresSummary::Batch joinedBatch(const LeastSquaresSummary::Batch& a,
                                       const LeastSquaresSummary::Batch& b) {
  LeastSquaresSummary::Batch out;
  out.samples = a.samples + b.samples;
  for (std::size_t j = 0; j < a.factors.size(); ++j)
    out.factors.push_back(stackedTriangularFactor(a.factors[j], b.factors[j]));
  return out;
}

/// InputError unless the supports are the same.
void requireSameLayout(int b, const std::vector<std::vector<int>>& mine, int other_b,
                       const std::vector<std::vector<int>>& other, const std::string& what) {
  if (b != other_b || mine != other)
    throw InputError(what + " of " + std::to_string(other_b) + " base parameters over " +
                     std::to_string(other.size()) + " joints does not match a summary of " +
                     std::to_string(b) + " over " + std::to_string(mine.size()) +
                     " (another robot, drive terms or base parameters)");
}

}  // namespace

LeastSquaresSummary::LeastSquaresSummary(const BaseParameters& base, const Model& model)
    : b_(base.numBase()), support_(jointSupport(base, model).support) {
  fitted_rows_ = Eigen::VectorXd::Zero(model.numJoints());
  tau_squared_ = Eigen::VectorXd::Zero(model.numJoints());
}

LeastSquaresSummary::LeastSquaresSummary(int num_base, std::vector<std::vector<int>> support,
                                         std::vector<Batch> batches, Eigen::VectorXd fitted_rows,
                                         Eigen::VectorXd tau_squared, double max_abs_tau)
    : b_(num_base),
      support_(std::move(support)),
      batches_(std::move(batches)),
      fitted_rows_(std::move(fitted_rows)),
      tau_squared_(std::move(tau_squared)),
      max_abs_tau_(max_abs_tau) {
  const auto n = static_cast<Eigen::Index>(support_.size());
  if (b_ < 1 || n < 1) throw InputError("a summary needs base parameters and joints");
  for (std::size_t j = 0; j < support_.size(); ++j)
    for (std::size_t c = 0; c < support_[j].size(); ++c)
      if (support_[j][c] < 0 || support_[j][c] >= b_ ||
          (c > 0 && support_[j][c] <= support_[j][c - 1]))
        throw InputError("joint " + std::to_string(j + 1) +
                         "'s support is not increasing base columns below " + std::to_string(b_));
  if (fitted_rows_.size() != n || tau_squared_.size() != n || !fitted_rows_.allFinite() ||
      !tau_squared_.allFinite() || !std::isfinite(max_abs_tau_) || max_abs_tau_ < 0.0 ||
      tau_squared_.minCoeff() < 0.0)
    throw InputError("a summary's totals are not one finite value per joint");
  for (const Batch& batch : batches_) {
    if (batch.samples < 1 || batch.factors.size() != support_.size())
      throw InputError("a summary's batch has no samples or not one factor per joint");
    for (std::size_t j = 0; j < support_.size(); ++j) {
      const Eigen::MatrixXd& r = batch.factors[j];
      const auto cols = static_cast<Eigen::Index>(support_[j].size()) + 1;
      if (r.rows() != cols || r.cols() != cols || !r.allFinite() ||
          !r.triangularView<Eigen::StrictlyLower>().toDenseMatrix().isZero(0.0))
        throw InputError("a summary's factor of joint " + std::to_string(j + 1) +
                         " is not an upper triangular, finite " + std::to_string(cols) +
                         "-square matrix");
    }
    samples_ += batch.samples;
  }
  if ((fitted_rows_.array() < 0.0).any() ||
      (fitted_rows_.array() > static_cast<double>(samples_)).any())
    throw InputError("a summary's fitted rows exceed its samples (" + std::to_string(samples_) +
                     ")");
}

void LeastSquaresSummary::joinBatchesBeyond(int most) {
  if (most < 1) throw InputError("a summary keeps at least one batch, not " + std::to_string(most));
  while (static_cast<int>(batches_.size()) > most) {
    std::vector<Batch> joined;
    for (std::size_t i = 0; i < batches_.size(); i += 2)
      joined.push_back(i + 1 < batches_.size() ? joinedBatch(batches_[i], batches_[i + 1])
                                               : std::move(batches_[i]));
    batches_ = std::move(joined);
  }
}

void LeastSquaresSummary::merge(const LeastSquaresSummary& other) {
  if (&other == this) {  // its batches appended to themselves: from a copy
    const LeastSquaresSummary copy = other;
    merge(copy);
    return;
  }
  if (support_.empty()) {  // an empty summary takes the other's layout
    *this = other;
    return;
  }
  requireSameLayout(b_, support_, other.b_, other.support_, "a summary");
  batches_.insert(batches_.end(), other.batches_.begin(), other.batches_.end());
  samples_ += other.samples_;
  fitted_rows_ += other.fitted_rows_;
  tau_squared_ += other.tau_squared_;
  max_abs_tau_ = std::max(max_abs_tau_, other.max_abs_tau_);
  joinBatchesBeyond(kMaxSummaryBatches);
}

void LeastSquaresSummary::addTo(LeastSquaresStream& stream) const {
  requireSameLayout(b_, support_, b_, stream.support(), "a least-squares stream");
  std::vector<Eigen::MatrixXd> factors;
  for (std::size_t j = 0; j < support_.size(); ++j) {
    const auto cols = static_cast<Eigen::Index>(support_[j].size()) + 1;
    TallQr qr(cols, std::max<Eigen::Index>(cols, 8 * cols));
    for (const Batch& batch : batches_) qr.add(batch.factors[j]);
    factors.push_back(batches_.empty() ? Eigen::MatrixXd::Zero(cols, cols) : qr.r());
  }
  stream.addFactors(factors, samples_, fitted_rows_, tau_squared_, max_abs_tau_);
}

std::vector<ScoreBatch> LeastSquaresSummary::scoreBatches(const Eigen::VectorXd& weights,
                                                          const Eigen::VectorXd& beta) const {
  if (weights.size() != numJoints() || beta.size() != b_)
    throw InputError("scoreBatches: " + std::to_string(weights.size()) + " weights and " +
                     std::to_string(beta.size()) + " base parameters for a summary of " +
                     std::to_string(numJoints()) + " joints and " + std::to_string(b_));
  std::vector<ScoreBatch> out;
  out.reserve(batches_.size());
  for (const Batch& batch : batches_) {
    ScoreBatch s{Eigen::VectorXd::Zero(b_), Eigen::MatrixXd::Zero(b_, b_)};
    for (std::size_t j = 0; j < support_.size(); ++j) {
      const std::vector<int>& support = support_[j];
      const auto p = static_cast<Eigen::Index>(support.size());
      const Eigen::MatrixXd& r = batch.factors[j];
      Eigen::VectorXd x(p + 1);  // [-beta(support); 1]: R x is the batch's residual, rotated
      for (Eigen::Index c = 0; c < p; ++c) x[c] = -beta[support[static_cast<std::size_t>(c)]];
      x[p] = 1.0;
      const Eigen::VectorXd residual = r * x;
      const auto rows = r.leftCols(p);
      const Eigen::VectorXd score =
          weights[static_cast<Eigen::Index>(j)] * (rows.transpose() * residual);
      const Eigen::MatrixXd normal =
          weights[static_cast<Eigen::Index>(j)] * (rows.transpose() * rows);
      for (Eigen::Index c = 0; c < p; ++c) {
        const int bc = support[static_cast<std::size_t>(c)];
        s.score[bc] += score[c];
        for (Eigen::Index d = 0; d < p; ++d)
          s.normal(bc, support[static_cast<std::size_t>(d)]) += normal(c, d);
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

long long LeastSquaresSummary::numValues() const {
  long long per_batch = 0;
  for (const std::vector<int>& s : support_) {
    const auto c = static_cast<long long>(s.size()) + 1;
    per_batch += c * (c + 1) / 2;
  }
  return per_batch * static_cast<long long>(batches_.size());
}

// ---- the builder ----

struct SummaryBuilder::Open {
  std::vector<TallQr> factors;  // per joint
};

SummaryBuilder::SummaryBuilder(const BaseParameters& base, const Model& model)
    : base_(base), summary_(base, model), open_(std::make_unique<Open>()) {
  gather_ = regressorOffsets(summary_.support_, model.numJoints(), &base.independent);
  for (const std::vector<int>& support : summary_.support_)
    open_->factors.emplace_back(static_cast<Eigen::Index>(support.size()) + 1);
}

SummaryBuilder::SummaryBuilder(SummaryBuilder&&) noexcept = default;
SummaryBuilder::~SummaryBuilder() = default;

void SummaryBuilder::closeBatch() {
  if (open_samples_ == 0) return;
  LeastSquaresSummary::Batch batch;
  batch.samples = open_samples_;
  for (TallQr& factor : open_->factors) {
    batch.factors.push_back(factor.r());
    factor.reset();
  }
  summary_.batches_.push_back(std::move(batch));
  summary_.samples_ += open_samples_;
  open_samples_ = 0;
  if (static_cast<int>(summary_.batches_.size()) >= 2 * kSummaryBatches) {
    summary_.joinBatchesBeyond(kSummaryBatches);
    batch_length_ *= 2;
  }
}

void SummaryBuilder::addTrajectory(const Model& model, const Trajectory& data, ThreadPool* pool,
                                   const FitRows* rows) {
  const int n = summary_.numJoints();
  if (data.numJoints() != n || model.numJoints() != n ||
      model.parameterLayout().size() != base_.numStandard())
    throw InputError("the data has " + std::to_string(data.numJoints()) + " joints, model '" +
                     model.name + "' " + std::to_string(model.numJoints()) + ", the summary " +
                     std::to_string(n));
  checkFiniteSamples(data);
  const int m = data.numSamples();
  const int threads = pool ? pool->numThreads() : 1;
  if (static_cast<int>(workspaces_.size()) < threads)
    workspaces_.resize(static_cast<std::size_t>(threads));
  if (static_cast<int>(adjusted_.size()) < threads)
    adjusted_.resize(static_cast<std::size_t>(threads));
  for (int done = 0; done < m;) {
    // The samples up to the open batch's end: their rows, then each joint's folded in order.
    const int count =
        static_cast<int>(std::min<long long>(m - done, batch_length_ - open_samples_));
    const long long first = numSamples();
    // The rows' buffers, kept from call to call (grown, never shrunk): freeing and allocating a
    // megabyte per chunk costs page faults, five times the work under a low malloc trim threshold
    // (a Dask worker's 64 KiB).
    if (taus_.cols() < count) {
      buffers_.clear();
      for (int j = 0; j < n; ++j)
        buffers_.emplace_back(
            count, static_cast<Eigen::Index>(gather_[static_cast<std::size_t>(j)].size()) + 1);
      taus_.resize(n, count);
    }
    std::vector<TallQr::RowMajorMatrix>& buffers = buffers_;
    Eigen::MatrixXd& taus = taus_;
    constexpr int kBlock = 64;
    const int tasks = (count + kBlock - 1) / kBlock;
    const auto task = [&](int index, int thread) {
      std::unique_ptr<Data>& own = workspaces_[static_cast<std::size_t>(thread)];
      if (!own) own = std::make_unique<Data>(model);
      Eigen::MatrixXd& adjusted = adjusted_[static_cast<std::size_t>(thread)];
      for (int k = index * kBlock; k < std::min(count, (index + 1) * kBlock); ++k) {
        const int sample = done + k;
        // The workspace's regressor as it is; a copy only for the rows FitRows changes.
        const Eigen::MatrixXd* regressor = &jointTorqueRegressor(
            model, *own, data.q.col(sample), data.dq.col(sample), data.ddq.col(sample));
        taus.col(k) = data.tau.col(sample);
        if (rows) {
          adjusted = *regressor;
          rows->apply(first + k, data.dq.col(sample), adjusted, taus.col(k));
          regressor = &adjusted;
        }
        const double* y = regressor->data();
        for (int j = 0; j < n; ++j) {
          const std::vector<Eigen::Index>& gather = gather_[static_cast<std::size_t>(j)];
          auto row = buffers[static_cast<std::size_t>(j)].row(k);
          for (std::size_t c = 0; c < gather.size(); ++c)
            row[static_cast<Eigen::Index>(c)] = y[gather[c]];
          row[static_cast<Eigen::Index>(gather.size())] = taus(j, k);
        }
      }
    };
    const auto fold = [&](int j, int) {
      open_->factors[static_cast<std::size_t>(j)].addRowMajor(
          buffers[static_cast<std::size_t>(j)].topRows(count));
    };
    if (pool) {
      pool->parallelFor(tasks, task);
      pool->parallelFor(n, fold);
    } else {
      for (int i = 0; i < tasks; ++i) task(i, 0);
      for (int j = 0; j < n; ++j) fold(j, 0);
    }
    for (int k = 0; k < count; ++k) {  // in order: the same sums for any thread count
      const int sample = done + k;
      for (int j = 0; j < n; ++j) {
        const bool fitted = !rows || rows->fitted(first + k, j, data.dq(j, sample));
        if (fitted) summary_.fitted_rows_[j] += 1.0;
      }
      summary_.tau_squared_ += taus.col(k).cwiseAbs2();
      summary_.max_abs_tau_ = std::max(summary_.max_abs_tau_, taus.col(k).cwiseAbs().maxCoeff());
    }
    open_samples_ += count;
    done += count;
    if (open_samples_ == batch_length_) closeBatch();
  }
}

LeastSquaresSummary SummaryBuilder::finish() {
  closeBatch();
  return std::move(summary_);
}

}  // namespace dynid
