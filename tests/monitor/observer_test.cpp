#include "analysis/monitor/observer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/parameters.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "tests/common/monitor_logs.hpp"

namespace dynid {
namespace {

using test::jointPush;
using test::pushedPuma;

// The observer's residual is the external torque through a first-order lag 1/K: a step of 10 N m
// shows 10 (1 - exp(-K t)) after t, and nothing without contact.
TEST(MomentumObserver, FollowsAStepOfExternalTorqueThroughItsLag) {
  const Model model = makePuma560();
  const Trajectory tr = pushedPuma(model, 1.5, {jointPush(1, 10.0, 1.0, 0.4)});
  MomentumObserver observer(model, Eigen::VectorXd::Constant(6, 100.0));
  double before = 0.0;
  for (int k = 0; k < tr.numSamples(); ++k) {
    const Eigen::VectorXd& r =
        observer.update(tr.time[k], tr.q.col(k), tr.dq.col(k), tr.tau.col(k));
    const double t = tr.time[k];
    if (t < 1.0) before = std::max(before, r.cwiseAbs().maxCoeff());
    if (t > 1.0 && t < 1.4) {
      // The trapezoid rule leads the continuous lag by half a step (0.5 ms).
      const double expected = 10.0 * (1.0 - std::exp(-100.0 * (t - 1.0 + 0.5e-3)));
      // Its remaining error: ~5 % of 10 N m at the step's first sample (1 ms = 0.1 time
      // constants); after, the simulation holds each sample's torque for 1 ms where the rule
      // assumes a ramp, which leaves < 1 % of the push while the controller reacts (0.066 seen).
      EXPECT_NEAR(r[1], expected, t < 1.01 ? 0.6 : 0.1) << t;
      // The push's momentum change reaches the other joints through M; the same discretisation
      // error leaves ~0.07 N m there while the residual rises.
      EXPECT_LT(std::abs(r[0]) + std::abs(r[2]), 0.1) << t;
    }
  }
  // Without contact: the held torque against the rule's ramp only (0.015 N m seen on 1 ms steps
  // of a 0.2-0.6 Hz motion).
  EXPECT_LT(before, 0.03);
}

TEST(MomentumObserver, IrregularSamplingAndARestart) {
  const Model model = makePuma560();
  const Trajectory tr = pushedPuma(model, 2.0, {});
  MomentumObserver observer(model, Eigen::VectorXd::Constant(6, 50.0));
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> skip(1, 4);  // steps of 1..4 ms
  double worst = 0.0;
  for (int k = 0; k < tr.numSamples(); k += skip(rng)) {
    if (k > 1000 && k < 1005) observer.restart();
    const Eigen::VectorXd& r =
        observer.update(tr.time[k], tr.q.col(k), tr.dq.col(k), tr.tau.col(k));
    worst = std::max(worst, r.cwiseAbs().maxCoeff());
  }
  // The trapezoid rule over steps of up to 4 ms of smooth motion: still well below 0.1 N m.
  EXPECT_LT(worst, 0.02);
  EXPECT_THROW(MomentumObserver(model, Eigen::VectorXd::Constant(5, 50.0)), InputError);
  EXPECT_THROW(MomentumObserver(model, Eigen::VectorXd::Constant(6, 0.0)), InputError);
}

// On a Gaussian AR(1) process the thresholds follow Rice's formula (the Gumbel law of the 1 s
// maxima agrees); spikes that the RMS does not show raise them through the Gumbel law.
TEST(Thresholds, RiceOnAGaussianProcessGumbelOnHeavyTails) {
  ResidualStatistics gaussian, spiky;
  gaussian.reset(2);
  spiky.reset(1);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(2), previous, s(1), s_previous(1);
  const double dt = 1e-3, a = 0.95;
  for (int k = 0; k < 200000; ++k) {
    previous = r;
    s_previous = s;
    r[0] = a * r[0] + std::sqrt(1 - a * a) * normal(rng);
    r[1] = 0.1 * r[0];
    s[0] = r[0] + ((k % 2000) < 5 ? 8.0 : 0.0);  // every 2 s, 5 ms at 8 sigma
    gaussian.add(r, k > 0 ? &previous : nullptr, dt);
    spiky.add(s, k > 0 ? &s_previous : nullptr, dt);
  }
  const Eigen::VectorXd sd = gaussian.rms(), rate_sd = gaussian.rateRms();
  // 200000 correlated samples (~10000 independent): RMS within a few percent of 1.
  EXPECT_NEAR(sd[0], 1.0, 0.05);
  EXPECT_NEAR(sd[1], 0.1, 0.005);
  EXPECT_EQ(gaussian.blocks, 199);
  const double rate = 1e-6;
  const Eigen::VectorXd u = riceThresholds(gaussian, rate);
  const double rice = sd[0] * std::sqrt(2.0 * std::log(rate_sd[0] / (M_PI * sd[0] * rate)));
  EXPECT_GE(u[0], rice);
  // The Gumbel fit to 199 maxima of a Gaussian process: within 20 % of Rice's level.
  EXPECT_LT(u[0], 1.2 * rice);
  EXPECT_NEAR(u[1] / u[0], 0.1, 1e-9);  // scale-invariant
  // A frequent rate gives a threshold below the largest value seen: the floor holds.
  EXPECT_EQ(riceThresholds(gaussian, 1.0)[0], gaussian.max_abs[0]);
  // Spikes of 8 sigma every 2 s: the RMS grows little, Rice's level stays near the Gaussian's,
  // but the block maxima carry them above 8.
  const Eigen::VectorXd heavy = riceThresholds(spiky, rate);
  EXPECT_GT(heavy[0], 9.0);
  EXPECT_GT(heavy[0], 1.5 * rice);
}

TEST(ResidualEnvelope, KeepsTheRangeOfEveryBucketInConstantMemory) {
  ResidualEnvelope env;
  env.reset(1);
  const int samples = 3 * ResidualEnvelope::kMaxBuckets * 4 + 5;
  for (int k = 0; k < samples; ++k) {
    Eigen::VectorXd r(1);
    r[0] = k == 10000 ? 50.0 : std::sin(0.01 * k);
    env.add(k * 1e-3, r);
  }
  EXPECT_LE(env.count(), 2 * ResidualEnvelope::kMaxBuckets);
  EXPECT_GE(env.count(), ResidualEnvelope::kMaxBuckets);
  EXPECT_EQ(env.high().maxCoeff(), 50.0);  // a one-sample spike survives the merges
  EXPECT_NEAR(env.low().minCoeff(), -1.0, 1e-4);
}

}  // namespace
}  // namespace dynid
