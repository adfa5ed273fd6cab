#include "analysis/logs/rest.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

constexpr double kRate = 1000.0;  // Hz, the rate dynid prepare resamples to by default

Eigen::VectorXd stamps(int n) { return Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / kRate); }

/// White Gaussian noise of standard deviation sigma, n samples.
Eigen::RowVectorXd noise(int n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, sigma);
  Eigen::RowVectorXd out(n);
  for (int k = 0; k < n; ++k) out[k] = gauss(rng);
  return out;
}

/// x smoothed by a centred moving average of `width` samples (filtered noise: correlated over
/// tens of samples, as a prepared log's velocity at rest is).
Eigen::RowVectorXd movingAverage(const Eigen::RowVectorXd& x, int width) {
  Eigen::RowVectorXd out = Eigen::RowVectorXd::Zero(x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    int count = 0;
    for (Eigen::Index i = std::max<Eigen::Index>(0, k - width / 2);
         i <= std::min<Eigen::Index>(x.size() - 1, k + width / 2); ++i, ++count)
      out[k] += x[i];
    out[k] /= count;
  }
  return out;
}

TEST(RestVelocity, WhiteNoiseAtRestIsThreeSigmaOfIt) {
  const int n = 5000;
  const double sigma = 1e-3;
  Eigen::MatrixXd dq(1, n);
  dq.row(0) = noise(n, sigma, 1);
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  // 3 sigma from 5000 samples: the MAD's spread is ~2 % of sigma, the chatter's 99th percentile
  // of |N(0, sigma)| is 2.58 sigma; 10 % covers both.
  EXPECT_NEAR(r.noise_level, 3.0 * sigma, 0.3 * sigma);
  EXPECT_NEAR(r.velocity, 3.0 * sigma, 0.3 * sigma);
  EXPECT_EQ(r.samples, n);
  EXPECT_GT(r.samples_at_rest, 0.99 * n);  // 3 sigma holds 99.7 %
}

TEST(RestVelocity, FilteredNoiseAtRestIsFoundFromItsChatter) {
  // A 40-sample moving average: the local fit follows the noise (noise_level far below its
  // spread), but its sign runs are a few tens of ms: the chatter sets the velocity.
  const int n = 20000;
  Eigen::MatrixXd dq(1, n);
  dq.row(0) = movingAverage(noise(n, 1e-3, 2), 40);
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  EXPECT_EQ(r.source(), "chatter");
  EXPECT_GT(r.chatter_runs, 100);
  EXPECT_LT(r.noise_level, 0.5 * r.chatter_level);
  // 99 % of the chattering samples' |dq|, so at least 98 % of the log (long runs excluded).
  EXPECT_GT(r.samples_at_rest, 0.98 * n);
}

// A joint hunting in its static friction after stops: white noise at rest, and every 0.5 s a slip
// of 50 ms at up to 15 sigma, alternately either way. The slips are motion, not the noise's
// chatter: the rest velocity stays the white noise's 3 sigma (the 99th percentile of the short
// runs would take the slips' speed).
TEST(RestVelocity, SlipsOfAHuntingJointAreMotionNotChatter) {
  const int n = 20000;
  const double sigma = 1e-3;
  Eigen::MatrixXd dq(1, n);
  dq.row(0) = noise(n, sigma, 5);
  for (int start = 250, slip = 0; start + 50 < n; start += 500, ++slip)
    for (int k = 0; k < 50; ++k)
      dq(0, start + k) += (slip % 2 ? -15.0 : 15.0) * sigma * std::sin(std::numbers::pi * k / 50.0);
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  EXPECT_EQ(r.source(), "noise");
  EXPECT_EQ(r.chatter_level, 0.0);
  // 3 sigma from 20000 samples, 10 % of them in slips that shift the MAD a little: 10 %.
  EXPECT_NEAR(r.velocity, 3.0 * sigma, 0.3 * sigma);
}

TEST(RestVelocity, CleanMotionHasNoRestButItsZeros) {
  // A 0.5 Hz sinusoid of 1 rad/s, no noise: reversals cross zero once each, nothing chatters.
  const int n = 8000;
  Eigen::MatrixXd dq(1, n);
  for (int k = 0; k < n; ++k) dq(0, k) = std::sin(std::numbers::pi * k / kRate);
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  EXPECT_EQ(r.chatter_level, 0.0);
  EXPECT_LT(r.noise_level, 1e-6);  // the local quadratic fit's residual on a smooth signal
  EXPECT_EQ(r.velocity, kRestVelocityFloor);
  EXPECT_EQ(r.source(), "floor");
  // Only the 8 samples on the crossings (k = 0, 1000, ..., 7000): dq leaves the 1e-5 rad/s band
  // within 3 us of a crossing at pi rad/s^2.
  EXPECT_LE(r.samples_at_rest, 8);
}

TEST(RestVelocity, StopsBetweenMovesAreAtRestAndTheMovesAreNot) {
  // 1 s moves (a half sine of 0.5 rad/s peak) between 1 s holds, white noise of 2e-4 rad/s.
  const int n = 10000;
  Eigen::MatrixXd dq(1, n);
  dq.row(0) = noise(n, 2e-4, 3);
  long moving = 0;
  for (int k = 0; k < n; ++k)
    if ((k / 1000) % 2 == 1) {
      dq(0, k) += 0.5 * std::sin(std::numbers::pi * (k % 1000) / 1000.0);
      moving += 1;
    }
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  EXPECT_GT(r.velocity, 2.0 * 2e-4);
  EXPECT_LT(r.velocity, 5.0 * 2e-4);
  // The holds' samples (5000) are at rest, the moves' only within ~2 ms of their ends.
  EXPECT_GT(r.samples_at_rest, 0.99 * (n - moving));
  EXPECT_LT(r.samples_at_rest, (n - moving) + 50);
}

TEST(RestVelocity, ALogCutAfterAReversalIsNotChatter) {
  // A 0.5 Hz sinusoid of 1 rad/s whose reversals stick and slip (the sign flips in bursts of
  // 1-5 ms runs at 3e-3 rad/s), the log cut 0.13 s after a reversal, in motion: that last run is
  // short only because the log ends, and its 0.4 rad/s are motion, not chatter.
  const int n = 5130;  // reversals at 1, 2, 3, 4 and 5 s
  Eigen::MatrixXd dq(1, n);
  for (int k = 0; k < n; ++k) {
    dq(0, k) = std::sin(std::numbers::pi * k / kRate);
    const int phase = k % 1000;
    if (phase < 20 || phase > 980) dq(0, k) = (k / 3 % 2 == 0 ? 3e-3 : -3e-3);  // the bursts
  }
  const RestVelocity r = measureRestVelocities(dq, stamps(n))[0];
  EXPECT_EQ(r.source(), "chatter");
  EXPECT_NEAR(r.chatter_level, 3e-3, 1e-9);  // the bursts' level (0.38 rad/s counting the end)
  // The first run (from the log's start) is cut too: a log that starts 0.13 s before a reversal.
  Eigen::MatrixXd reversed = dq.rowwise().reverse();
  EXPECT_NEAR(measureRestVelocities(reversed, stamps(n))[0].chatter_level, 3e-3, 1e-9);
}

TEST(RestVelocity, GivenVelocitiesAreCheckedAndCounted) {
  Eigen::MatrixXd dq(2, 3);
  dq << 0.0, 1e-4, 0.1, -2e-3, 0.5, 1e-3;
  const std::vector<RestVelocity> one = givenRestVelocities({1e-3}, dq);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].samples_at_rest, 2);
  EXPECT_EQ(one[1].samples_at_rest, 1);  // |dq| <= rest: 1e-3 is at rest
  EXPECT_EQ(one[1].source(), "given");
  EXPECT_EQ(restThresholds(givenRestVelocities({1e-3, 2e-3}, dq))[1], 2e-3);
  for (const std::vector<double>& bad :
       {std::vector<double>{1.0, 2.0, 3.0}, std::vector<double>{-1.0}, std::vector<double>{NAN}}) {
    try {
      givenRestVelocities(bad, dq);
      FAIL() << "accepted a bad rest velocity";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("`rest_velocity`"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(measureRestVelocities(dq, Eigen::VectorXd::Zero(2)), InputError);
}

}  // namespace
}  // namespace dynid
