#include "analysis/estimation/covariance.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "tests/common/identification.hpp"

namespace dynid {
namespace {

/// A PUMA log with drives and white torque noise, its OLS and WLS estimates from a stream.
struct CovarianceFixture {
  Model model = makePuma560(true);
  Trajectory data = test::pumaTrajectory(model, 3.0, 0.3, 7);
  BaseParameters base = structuralBaseParameters(model);
  BaseEstimate estimate(LeastSquaresMethod method) {
    LeastSquaresStream stream(base, model);
    stream.addTrajectory(model, data);
    return stream.estimate(method);
  }
  TrainingReplay replay(int chunk) const {
    return [this, chunk](const std::function<void(const Trajectory&)>& each) {
      for (int first = 0; first < data.numSamples(); first += chunk) {
        const int count = std::min(chunk, data.numSamples() - first);
        Trajectory part;
        part.time = data.time.segment(first, count);
        part.q = data.q.middleCols(first, count);
        part.dq = data.dq.middleCols(first, count);
        part.ddq = data.ddq.middleCols(first, count);
        part.tau = data.tau.middleCols(first, count);
        each(part);
      }
    };
  }
};

TEST(Covariance, TheReplayAndTheObservationGiveTheSameCovarianceForAnyThreadsAndChunks) {
  CovarianceFixture s;
  const Observation observation = observationFromTrajectory(s.model, s.data);
  for (const LeastSquaresMethod method :
       {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    const BaseEstimate white = s.estimate(method);
    const ScoreWeights weights = scoreWeights(white, method == LeastSquaresMethod::kWeighted);
    BaseEstimate dense = white;
    const CovarianceSummary summary = applyHacCovariance(s.base, observation, weights, dense);
    EXPECT_EQ(summary.policy, "hac");
    EXPECT_EQ(summary.batch, 16);  // 3001 samples in 256 batches; white noise asks for 1
    // White noise: the median standard deviation within the random error of 188 batches.
    EXPECT_NEAR(summary.inflation, 1.0, 0.15);
    EXPECT_EQ(dense.beta, white.beta);  // the estimate itself is untouched
    for (int threads : {1, 3}) {
      ThreadPool pool(threads);
      for (int chunk : {100, 2048, 5000}) {
        BaseEstimate streamed = white;
        applyHacCovariance(s.model, s.base, s.replay(chunk), &pool, weights, streamed);
        // The same numbers in the same order (the replay's rows are the regressor's, the
        // observation's the same regressor's): equal to round-off of the QR's estimate.
        EXPECT_LT((streamed.covariance - dense.covariance).norm(), 1e-9 * dense.covariance.norm())
            << threads << " threads, chunks of " << chunk;
        EXPECT_EQ(streamed.std_dev.size(), s.base.numBase());
      }
    }
  }
}

TEST(Covariance, PolicyNamesAndARefusedReplay) {
  EXPECT_EQ(covariancePolicyFrom("hac"), CovariancePolicy::kHac);
  EXPECT_EQ(covariancePolicyFrom("white"), CovariancePolicy::kWhite);
  EXPECT_STREQ(covariancePolicyName(CovariancePolicy::kHac), "hac");
  EXPECT_THROW(covariancePolicyFrom("newey-west"), InputError);
  CovarianceFixture s;
  BaseEstimate e = s.estimate(LeastSquaresMethod::kOrdinary);
  // A replay of other data than the estimate's: refused, not a covariance of the wrong samples.
  const TrainingReplay half = [&](const std::function<void(const Trajectory&)>& each) {
    s.replay(1000)([&](const Trajectory& part) {
      if (part.time[0] < 1.0) each(part);
    });
  };
  EXPECT_THROW(applyHacCovariance(s.model, s.base, half, nullptr, scoreWeights(e, false), e),
               InputError);
}

}  // namespace
}  // namespace dynid
