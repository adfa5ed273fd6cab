#include "analysis/estimation/covariance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "identifiability/uncertainty/score_covariance.hpp"

namespace dynid {

const char* covariancePolicyName(CovariancePolicy policy) {
  return policy == CovariancePolicy::kWhite ? "white" : "hac";
}

CovariancePolicy covariancePolicyFrom(const std::string& name) {
  if (name == "hac") return CovariancePolicy::kHac;
  if (name == "white") return CovariancePolicy::kWhite;
  throw InputError("unknown covariance policy '" + name + "' (expected hac or white)");
}

ScoreWeights scoreWeights(const BaseEstimate& estimate, bool weighted) {
  const Eigen::Index n = estimate.residual_rms.size();
  ScoreWeights out;
  out.per_joint = Eigen::VectorXd::Ones(n);
  if (!weighted) return out;
  // As the stream weighs: a joint whose residual vanishes gets a floor, not an infinite weight.
  const double floor = 1e-15 * (1.0 + estimate.measured_rms.maxCoeff());
  for (Eigen::Index j = 0; j < n; ++j)
    out.per_joint[j] = 1.0 / std::pow(std::max(estimate.joint_sigma[j], floor), 2);
  return out;
}

namespace {

constexpr int kReplayBlock = 64;  // samples per parallel task of the replay

/// Replaces the estimate's (white) covariance by `robust` and says how much wider it is.
CovarianceSummary installRobust(const Eigen::MatrixXd& robust, int batch,
                                std::vector<double> autocorrelation, BaseEstimate& estimate,
                                PhysicalEstimate* pc) {
  const Eigen::Index b = estimate.beta.size();
  const Eigen::MatrixXd white = estimate.covariance;
  CovarianceSummary out;
  out.policy = covariancePolicyName(CovariancePolicy::kHac);
  out.batch = batch;
  out.autocorrelation = std::move(autocorrelation);
  std::vector<double> ratios;
  for (Eigen::Index k = 0; k < b; ++k)
    if (white(k, k) > 0.0 && robust(k, k) >= 0.0)
      ratios.push_back(std::sqrt(robust(k, k) / white(k, k)));
  if (!ratios.empty()) {
    std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2),
                     ratios.end());
    out.inflation = ratios[ratios.size() / 2];
  }
  estimate.covariance = robust;
  estimate.std_dev = robust.diagonal().cwiseMax(0.0).cwiseSqrt();
  estimate.relative_std_dev_percent.resize(b);
  for (Eigen::Index j = 0; j < b; ++j)
    estimate.relative_std_dev_percent[j] =
        estimate.beta[j] != 0.0 ? 100.0 * estimate.std_dev[j] / std::abs(estimate.beta[j])
                                : std::numeric_limits<double>::infinity();
  if (pc != nullptr) {
    pc->covariance = estimate.covariance;
    pc->std_dev = estimate.std_dev;
  }
  return out;
}

/// Folds each sample's weighted rows and residuals into the batches and sets the estimate's
/// covariance from them.
class Sandwich {
 public:
  Sandwich(const BaseParameters& base, const ScoreWeights& weights, const BaseEstimate& estimate)
      : b_(base.numBase()),
        n_(static_cast<int>(weights.per_joint.size())),
        root_(weights.per_joint.cwiseSqrt()),
        beta_(estimate.beta),
        scores_(b_, n_, estimate.num_samples) {}

  /// Samples [first, first + count) of the pass (their base regressor rows stacked, n per sample,
  /// and torques n x count) as a block: the rows weighted in place (Lambda^1/2 W1), the weighted
  /// residuals. Thread safe.
  ScoreCovariance::Block block(Eigen::Ref<Eigen::MatrixXd> w1,
                               const Eigen::Ref<const Eigen::MatrixXd>& tau) const {
    const Eigen::Index count = tau.cols();
    Eigen::MatrixXd residuals(n_, count);
    for (Eigen::Index k = 0; k < count; ++k) {
      auto rows = w1.middleRows(k * n_, n_);
      residuals.col(k) = root_.cwiseProduct(tau.col(k) - rows * beta_);
      rows = root_.asDiagonal() * rows;
    }
    return ScoreCovariance::prepare(w1, residuals);
  }
  void add(const ScoreCovariance::Block& block) { scores_.add(block); }
  /// The blocks a run of `count` samples from sample `first` is cut into: at every multiple of
  /// kReplayBlock and of the stored batches' length (absolute sample indices, so that the cut, and
  /// so the sums' round-off, is the same for any chunking into multiples of kReplayBlock and any
  /// thread count). Pairs (offset, length) into the run.
  std::vector<std::pair<int, int>> cuts(long long first, int count) const;
  int b() const { return b_; }
  int n() const { return n_; }

  CovarianceSummary finish(BaseEstimate& estimate, PhysicalEstimate* pc) const {
    if (scores_.samples() != estimate.num_samples)
      throw InputError("the covariance's pass saw " + std::to_string(scores_.samples()) +
                       " samples, the estimate " + std::to_string(estimate.num_samples));
    return installRobust(scores_.covariance(), scores_.batch(), scores_.autocorrelation(), estimate,
                         pc);
  }

 private:
  int b_, n_;
  Eigen::VectorXd root_, beta_;
  ScoreCovariance scores_;
};

std::vector<std::pair<int, int>> Sandwich::cuts(long long first, int count) const {
  const long long storage = scores_.storageLength();
  std::vector<std::pair<int, int>> out;
  for (long long at = first; at < first + count;) {
    const long long next_block = (at / kReplayBlock + 1) * kReplayBlock;
    const long long next_batch = (at / storage + 1) * storage;
    const long long end = std::min({next_block, next_batch, first + count});
    out.emplace_back(static_cast<int>(at - first), static_cast<int>(end - at));
    at = end;
  }
  return out;
}

}  // namespace

CovarianceSummary applyHacCovariance(const Model& model, const BaseParameters& base,
                                     const TrainingReplay& replay, ThreadPool* pool,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc, const FitRows* rows) {
  Sandwich sandwich(base, weights, estimate);
  const int n = sandwich.n(), b = sandwich.b(), threads = pool ? pool->numThreads() : 1;
  std::vector<std::unique_ptr<Data>> workspaces(static_cast<std::size_t>(threads));
  long long first = 0;  // the chunk's first sample in the pass
  std::vector<ScoreCovariance::Block> blocks;
  replay([&](const Trajectory& chunk) {
    const std::vector<std::pair<int, int>> cuts = sandwich.cuts(first, chunk.numSamples());
    blocks.assign(cuts.size(), {});
    const auto task = [&](int index, int thread) {
      std::unique_ptr<Data>& data = workspaces[static_cast<std::size_t>(thread)];
      if (!data) data = std::make_unique<Data>(model);
      const auto [offset, count] = cuts[static_cast<std::size_t>(index)];
      Eigen::MatrixXd w1(static_cast<Eigen::Index>(n) * count, b);
      Eigen::MatrixXd tau = chunk.tau.middleCols(offset, count), adjusted;
      for (int k = 0; k < count; ++k) {
        const int sample = offset + k;
        const Eigen::MatrixXd* y = &jointTorqueRegressor(
            model, *data, chunk.q.col(sample), chunk.dq.col(sample), chunk.ddq.col(sample));
        if (rows) {  // the rows as the fit took them
          adjusted = *y;
          rows->apply(first + sample, chunk.dq.col(sample), adjusted, tau.col(k));
          y = &adjusted;
        }
        for (int c = 0; c < b; ++c)
          w1.col(c).segment(static_cast<Eigen::Index>(k) * n, n) =
              y->col(base.independent[static_cast<std::size_t>(c)]);
      }
      blocks[static_cast<std::size_t>(index)] = sandwich.block(w1, tau);
    };
    const int tasks = static_cast<int>(cuts.size());
    if (pool)
      pool->parallelFor(tasks, task);
    else
      for (int i = 0; i < tasks; ++i) task(i, 0);
    for (const ScoreCovariance::Block& block : blocks) sandwich.add(block);  // in order
    first += chunk.numSamples();
  });
  return sandwich.finish(estimate, pc);
}

CovarianceSummary applyHacCovariance(const LeastSquaresSummary& summary,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc) {
  if (summary.numSamples() != estimate.num_samples)
    throw InputError("the summary holds " + std::to_string(summary.numSamples()) +
                     " samples, the estimate " + std::to_string(estimate.num_samples));
  const std::vector<ScoreBatch> batches = summary.scoreBatches(weights.per_joint, estimate.beta);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(estimate.beta.size(), estimate.beta.size());
  long long longest = 0;
  for (std::size_t i = 0; i < batches.size(); ++i) {
    h += batches[i].normal;
    longest = std::max(longest, summary.batches()[i].samples);
  }
  return installRobust(robustCovariance(h, batches), static_cast<int>(longest), {}, estimate, pc);
}

CovarianceSummary applyHacCovariance(const BaseParameters& base, const Observation& observation,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc) {
  Sandwich sandwich(base, weights, estimate);
  const int n = observation.num_joints;
  Eigen::MatrixXd w1 = base.baseRegressor(observation.W);
  const Eigen::Map<const Eigen::MatrixXd> tau(observation.tau.data(), n, observation.num_samples);
  for (const auto& [offset, count] : sandwich.cuts(0, observation.num_samples))
    sandwich.add(sandwich.block(
        w1.middleRows(static_cast<Eigen::Index>(offset) * n, static_cast<Eigen::Index>(count) * n),
        tau.middleCols(offset, count)));
  return sandwich.finish(estimate, pc);
}

}  // namespace dynid
