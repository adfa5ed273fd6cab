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

  /// One sample's weighted rows (in place: W1_k becomes Lambda^1/2 W1_k) and weighted residuals.
  void at(Eigen::Ref<Eigen::MatrixXd> w1, const Eigen::Ref<const Eigen::VectorXd>& tau,
          Eigen::Ref<Eigen::VectorXd> residual) const {
    residual = root_.cwiseProduct(tau - w1 * beta_);
    w1 = root_.asDiagonal() * w1;
  }
  void add(const Eigen::Ref<const Eigen::MatrixXd>& rows,
           const Eigen::Ref<const Eigen::VectorXd>& residual) {
    scores_.add(rows, residual);
  }
  int b() const { return b_; }
  int n() const { return n_; }

  CovarianceSummary finish(BaseEstimate& estimate, PhysicalEstimate* pc) const {
    if (scores_.samples() != estimate.num_samples)
      throw InputError("the covariance's pass saw " + std::to_string(scores_.samples()) +
                       " samples, the estimate " + std::to_string(estimate.num_samples));
    const Eigen::MatrixXd white = estimate.covariance;
    const Eigen::MatrixXd robust = scores_.covariance();
    CovarianceSummary out;
    out.policy = covariancePolicyName(CovariancePolicy::kHac);
    out.batch = scores_.batch();
    out.autocorrelation = scores_.autocorrelation();
    std::vector<double> ratios;
    for (int k = 0; k < b_; ++k)
      if (white(k, k) > 0.0 && robust(k, k) >= 0.0)
        ratios.push_back(std::sqrt(robust(k, k) / white(k, k)));
    if (!ratios.empty()) {
      std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2),
                       ratios.end());
      out.inflation = ratios[ratios.size() / 2];
    }
    estimate.covariance = robust;
    estimate.std_dev = robust.diagonal().cwiseMax(0.0).cwiseSqrt();
    estimate.relative_std_dev_percent.resize(b_);
    for (int j = 0; j < b_; ++j)
      estimate.relative_std_dev_percent[j] =
          estimate.beta[j] != 0.0 ? 100.0 * estimate.std_dev[j] / std::abs(estimate.beta[j])
                                  : std::numeric_limits<double>::infinity();
    if (pc != nullptr) {
      pc->covariance = estimate.covariance;
      pc->std_dev = estimate.std_dev;
    }
    return out;
  }

 private:
  int b_, n_;
  Eigen::VectorXd root_, beta_;
  ScoreCovariance scores_;
};

constexpr int kReplayBlock = 64;  // samples per parallel task of the replay

}  // namespace

CovarianceSummary applyHacCovariance(const Model& model, const BaseParameters& base,
                                     const TrainingReplay& replay, ThreadPool* pool,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc) {
  Sandwich sandwich(base, weights, estimate);
  const int n = sandwich.n(), b = sandwich.b(), threads = pool ? pool->numThreads() : 1;
  std::vector<std::unique_ptr<Data>> workspaces(static_cast<std::size_t>(threads));
  Eigen::MatrixXd rows, residuals;  // a chunk's: n x (b m), n x m
  replay([&](const Trajectory& chunk) {
    const int m = chunk.numSamples();
    rows.resize(n, static_cast<Eigen::Index>(b) * m);
    residuals.resize(n, m);
    const auto block = [&](int index, int thread) {
      std::unique_ptr<Data>& data = workspaces[static_cast<std::size_t>(thread)];
      if (!data) data = std::make_unique<Data>(model);
      for (int k = index * kReplayBlock; k < std::min(m, (index + 1) * kReplayBlock); ++k) {
        const Eigen::MatrixXd& y =
            jointTorqueRegressor(model, *data, chunk.q.col(k), chunk.dq.col(k), chunk.ddq.col(k));
        auto w1 = rows.middleCols(static_cast<Eigen::Index>(k) * b, b);
        for (int c = 0; c < b; ++c)
          w1.col(c) = y.col(base.independent[static_cast<std::size_t>(c)]);
        sandwich.at(w1, chunk.tau.col(k), residuals.col(k));
      }
    };
    const int blocks = (m + kReplayBlock - 1) / kReplayBlock;
    if (pool)
      pool->parallelFor(blocks, block);
    else
      for (int i = 0; i < blocks; ++i) block(i, 0);
    for (int k = 0; k < m; ++k)  // in order
      sandwich.add(rows.middleCols(static_cast<Eigen::Index>(k) * b, b), residuals.col(k));
  });
  return sandwich.finish(estimate, pc);
}

CovarianceSummary applyHacCovariance(const BaseParameters& base, const Observation& observation,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc) {
  Sandwich sandwich(base, weights, estimate);
  const int n = observation.num_joints;
  Eigen::MatrixXd w1 = base.baseRegressor(observation.W);
  Eigen::VectorXd residual(n);
  for (int k = 0; k < observation.num_samples; ++k) {
    auto rows = w1.middleRows(static_cast<Eigen::Index>(k) * n, n);
    sandwich.at(rows, observation.tau.segment(static_cast<Eigen::Index>(k) * n, n), residual);
    sandwich.add(rows, residual);
  }
  return sandwich.finish(estimate, pc);
}

}  // namespace dynid
