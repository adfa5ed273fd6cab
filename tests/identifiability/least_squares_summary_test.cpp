#include "identifiability/least_squares_summary.hpp"

#include <gtest/gtest.h>

#include "tests/common/identification.hpp"
#include "tests/common/trajectories.hpp"

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/regressor.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

using test::concatenated;
using test::pumaBase;
using test::pumaTrajectory;

LeastSquaresSummary summaryOf(const Model& model, const BaseParameters& base,
                              const Trajectory& data, ThreadPool* pool = nullptr,
                              int chunk = 1 << 30) {
  SummaryBuilder builder(base, model);
  for (int at = 0; at < data.numSamples(); at += chunk)
    builder.addTrajectory(model, data.samples(at, std::min(chunk, data.numSamples() - at)), pool);
  return builder.finish();
}

BaseEstimate estimateOf(const Model& model, const BaseParameters& base,
                        const LeastSquaresSummary& summary, LeastSquaresMethod method) {
  LeastSquaresStream stream(base, model);
  summary.addTo(stream);
  return stream.estimate(method);
}

TEST(LeastSquaresSummary, MergedInAnyOrderGiveTheConcatenatedDatasEstimate) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const std::vector<Trajectory> logs = {pumaTrajectory(puma, 3.0, 0.5, 1),
                                        pumaTrajectory(puma, 2.0, 0.5, 2, 1.3),
                                        pumaTrajectory(puma, 4.0, 0.5, 3, 0.8)};
  LeastSquaresStream whole(base, puma);
  whole.addTrajectory(puma, concatenated(logs));
  std::vector<LeastSquaresSummary> parts;
  for (const Trajectory& log : logs) parts.push_back(summaryOf(puma, base, log));
  const std::vector<std::vector<int>> orders = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
  for (LeastSquaresMethod method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    const BaseEstimate reference = whole.estimate(method);
    for (const std::vector<int>& order : orders) {
      LeastSquaresSummary merged;
      for (int i : order) merged.merge(parts[static_cast<std::size_t>(i)]);
      const BaseEstimate e = estimateOf(puma, base, merged, method);
      // 1e-10 relative: both are backward-stable QR of the same rows (condition ~1e2-1e3 scaled),
      // stacked in another order.
      EXPECT_LT((e.beta - reference.beta).norm(), 1e-10 * reference.beta.norm());
      EXPECT_LT((e.residual_rms - reference.residual_rms).norm(),
                1e-10 * reference.residual_rms.norm());
      EXPECT_EQ(e.num_samples, reference.num_samples);
      EXPECT_EQ(e.fitted_rows, reference.fitted_rows);
      EXPECT_LT((e.measured_rms - reference.measured_rms).norm(),
                1e-12 * reference.measured_rms.norm());
      // The white covariance: the same sigma^2 (W1^T W1)^-1 to round-off (1e-8: an inverse).
      EXPECT_LT((e.covariance - reference.covariance).norm(), 1e-8 * reference.covariance.norm());
    }
  }
}

TEST(LeastSquaresSummary, TheSameBitsForAnyThreadCountAndChunking) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 3.0, 0.5, 4);
  const LeastSquaresSummary one = summaryOf(puma, base, data);
  ThreadPool two(2), three(3);
  for (const LeastSquaresSummary& other :
       {summaryOf(puma, base, data, &two, 100), summaryOf(puma, base, data, &three, 777)}) {
    ASSERT_EQ(other.batches().size(), one.batches().size());
    for (std::size_t b = 0; b < one.batches().size(); ++b)
      for (std::size_t j = 0; j < 6; ++j)
        EXPECT_EQ(other.batches()[b].factors[j], one.batches()[b].factors[j]);
    EXPECT_EQ(other.tauSquared(), one.tauSquared());
  }
}

TEST(LeastSquaresSummary, ItsBatchesGiveTheScoreCovarianceOfTheSameBatches) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 6.0, 0.5, 5);  // 6000 samples: 24 batches of 256
  const LeastSquaresSummary summary = summaryOf(puma, base, data);
  ASSERT_EQ(summary.batches().front().samples, kFirstSummaryBatch);
  const BaseEstimate ols = estimateOf(puma, base, summary, LeastSquaresMethod::kOrdinary);
  // The reference from the samples: each one's rows and residual at the estimate.
  ScoreCovariance reference(base.numBase(), 6, data.numSamples(),
                            static_cast<int>(kFirstSummaryBatch));
  Data workspace(puma);
  for (int k = 0; k < data.numSamples(); ++k) {
    const Eigen::MatrixXd w1 = base.baseRegressor(
        jointTorqueRegressor(puma, workspace, data.q.col(k), data.dq.col(k), data.ddq.col(k)));
    reference.add(w1, data.tau.col(k) - w1 * ols.beta);
  }
  const std::vector<ScoreBatch> batches = summary.scoreBatches(Eigen::VectorXd::Ones(6), ols.beta);
  ASSERT_EQ(batches.size(), 24u);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(base.numBase(), base.numBase());
  for (const ScoreBatch& b : batches) h += b.normal;
  const Eigen::MatrixXd covariance = robustCovariance(h, batches);
  const Eigen::MatrixXd expected = reference.covariance();
  // 1e-7 relative: the scores are differences of rotated residuals (R x) against sums of
  // products; both exact to round-off times the normal matrix's condition (~1e6 unscaled).
  EXPECT_LT((covariance - expected).norm(), 1e-7 * expected.norm());
}

TEST(LeastSquaresSummary, KeepsItsBatchesBoundedWhateverTheLength) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 20.0, 0.5, 6);  // 20001 samples
  const LeastSquaresSummary one = summaryOf(puma, base, data, nullptr, 3000);
  EXPECT_GE(static_cast<int>(one.batches().size()), kSummaryBatches);
  EXPECT_LT(static_cast<int>(one.batches().size()), 2 * kSummaryBatches);
  long long samples = 0;
  for (const LeastSquaresSummary::Batch& b : one.batches()) samples += b.samples;
  EXPECT_EQ(samples, data.numSamples());
  LeastSquaresSummary many;
  for (int i = 0; i < 12; ++i) many.merge(one);
  EXPECT_LE(static_cast<int>(many.batches().size()), kMaxSummaryBatches);
  EXPECT_EQ(many.numSamples(), 12LL * data.numSamples());
  // Twelve copies of one log: the same estimate as the log's (each row counted twelve times).
  const BaseEstimate a = estimateOf(puma, base, one, LeastSquaresMethod::kOrdinary);
  const BaseEstimate b = estimateOf(puma, base, many, LeastSquaresMethod::kOrdinary);
  EXPECT_LT((a.beta - b.beta).norm(), 1e-10 * a.beta.norm());  // round-off of a stacked QR
  // Joined beforehand to a share of the batches (a Dask task's): halved while above it, the
  // samples all kept, the same estimate; merged then, nothing more is joined.
  LeastSquaresSummary share = one;
  share.joinBatchesBeyond(kMaxSummaryBatches / 12);
  EXPECT_LE(static_cast<int>(share.batches().size()), kMaxSummaryBatches / 12);
  EXPECT_GT(static_cast<int>(share.batches().size()), kMaxSummaryBatches / 24);
  EXPECT_EQ(share.numSamples(), one.numSamples());
  const BaseEstimate c = estimateOf(puma, base, share, LeastSquaresMethod::kOrdinary);
  EXPECT_LT((a.beta - c.beta).norm(), 1e-10 * a.beta.norm());  // as above
  LeastSquaresSummary appended;
  for (int i = 0; i < 12; ++i) appended.merge(share);
  EXPECT_EQ(appended.batches().size(), 12 * share.batches().size());
  EXPECT_THROW(share.joinBatchesBeyond(0), InputError);
  // Merged with itself: its rows twice (its own batches read before they are appended to).
  LeastSquaresSummary twice = share;
  twice.merge(twice);
  EXPECT_EQ(twice.numSamples(), 2 * share.numSamples());
  EXPECT_EQ(twice.batches().size(), 2 * share.batches().size());
  EXPECT_EQ(twice.batches().back().factors, share.batches().back().factors);
}

TEST(LeastSquaresSummary, RefusesToMergeAnotherLayoutAndReadsOnlyConsistentParts) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  Model fewer = makePuma560(false);
  const BaseParameters fewer_base = pumaBase(fewer);
  const Trajectory data = pumaTrajectory(puma, 1.0, 0.5, 7);
  LeastSquaresSummary a = summaryOf(puma, base, data);
  Trajectory same = data;
  const LeastSquaresSummary b = summaryOf(fewer, fewer_base, same);
  EXPECT_THROW(a.merge(b), InputError);
  LeastSquaresStream other(fewer_base, fewer);
  EXPECT_THROW(a.addTo(other), InputError);
  // Parts: a factor that is not upper triangular, fitted rows beyond the samples.
  std::vector<LeastSquaresSummary::Batch> batches = a.batches();
  batches.front().factors.front()(1, 0) = 1.0;
  EXPECT_THROW(LeastSquaresSummary(a.numBase(), a.support(), batches, a.fittedRows(),
                                   a.tauSquared(), a.maxAbsTau()),
               InputError);
  EXPECT_THROW(LeastSquaresSummary(a.numBase(), a.support(), a.batches(), a.fittedRows() * 2.0,
                                   a.tauSquared(), a.maxAbsTau()),
               InputError);
  EXPECT_NO_THROW(LeastSquaresSummary(a.numBase(), a.support(), a.batches(), a.fittedRows(),
                                      a.tauSquared(), a.maxAbsTau()));
}

}  // namespace
}  // namespace dynid
