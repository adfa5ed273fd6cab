// The moving arm's regimes (analysis/monitor/regimes.hpp): each joint's speed class and whether it
// accelerates, the scales they are read against, and the threshold each regime gives.
#include "analysis/monitor/regimes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace dynid {
namespace {

constexpr double kPi = std::numbers::pi;

/// One joint on a sinusoid of amplitude A [rad/s] at f [Hz], sampled at 1 kHz.
struct Sinusoid {
  double A = 1.0, f = 0.5;
  double velocity(double t) const { return A * std::sin(2.0 * kPi * f * t); }
};

TEST(MovingRegimes, ScalesAreTheMotionsTopSpeedAndAcceleration) {
  const Sinusoid s;
  const int count = 20000;  // 20 s at 1 kHz, 10 periods, and 10 s held still after them
  Eigen::MatrixXd dq = Eigen::MatrixXd::Zero(2, count + 10000);
  Eigen::VectorXd time(count + 10000);
  for (int k = 0; k < time.size(); ++k) {
    time[k] = 1e-3 * k;
    if (k < count) dq(0, k) = s.velocity(time[k]);
  }
  const RegimeScales scales = measureRegimeScales(dq, time);
  // The 95th percentile of |A sin| over the moving samples is A sin(0.95 pi / 2) = 0.997 A; the
  // 20 ms smoothing lags by 2 pi f 20 ms and scales by 1 / sqrt(1 + (2 pi f 0.02)^2) (0.9980). The
  // held half of the log does not lower it (it counts the samples above 1 % of the largest only).
  const double lag = 1.0 / std::sqrt(1.0 + std::pow(2.0 * kPi * s.f * 0.02, 2.0));
  EXPECT_NEAR(scales.speed[0], 0.997 * s.A * lag, 2e-3);
  // The acceleration is smoothed twice: A 2 pi f, scaled twice.
  EXPECT_NEAR(scales.acceleration[0], 0.997 * s.A * 2.0 * kPi * s.f * lag * lag, 6e-3);
  EXPECT_EQ(scales.speed[1], 0.0);  // a joint that never moves has no scale
  EXPECT_EQ(scales.acceleration[1], 0.0);
}

TEST(MovingRegimes, SlowNearAReversalFastAtTheTopAndAcceleratingWhereItTurns) {
  const Sinusoid s;
  const double accel = s.A * 2.0 * kPi * s.f;  // the acceleration's amplitude
  MovingRegimes regimes;
  regimes.reset(Eigen::VectorXd::Constant(1, s.A), Eigen::VectorXd::Constant(1, accel));
  double t = 0.0;
  bool first = true;
  const auto regimeAt = [&](double until) {
    int out = -1;
    for (; t <= until + 1e-12; t += 1e-3) {
      out = regimes.update(t, first ? 0.0 : 1e-3, Eigen::VectorXd::Constant(1, s.velocity(t)))[0];
      first = false;
    }
    return out;
  };
  // The period is 2 s: reversals at 1 s, 2 s, ...; the top speed at 0.5 s, 1.5 s, ...
  regimeAt(2.0);  // settle the smoothing
  // At the top speed it is fast and steady (|a| = 0 there, below half its scale).
  EXPECT_EQ(regimeAt(2.5), regimeIndex(2, false));
  // Between: cruising (0.5 A < 0.7 A) and accelerating (|a| = 0.87 of its scale > 0.5).
  EXPECT_EQ(regimeAt(2.85), regimeIndex(1, true));
  // At the reversal (3 s): slow (the smoothing lags 20 ms) and accelerating (|a| is at its top).
  EXPECT_EQ(regimeAt(3.02), regimeIndex(0, true));
  // |v| reaches 0.1 A 32 ms after the reversal, 52 ms with the smoothing's lag: slow is kept
  // kRegimeMemorySeconds more, to 102 ms, then the joint is cruising.
  EXPECT_EQ(regimeAt(3.09), regimeIndex(0, true));
  EXPECT_EQ(regimeAt(3.12), regimeIndex(1, true));
}

TEST(MovingRegimes, AJointWithoutScalesStaysCruisingAndSteady) {
  MovingRegimes regimes;
  regimes.reset(Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(0.0, 1.0));
  regimes.update(0.0, 0.0, Eigen::Vector2d(0.0, 0.0));
  const Eigen::VectorXi r = regimes.update(1e-3, 1e-3, Eigen::Vector2d(0.0, 0.0));
  EXPECT_EQ(r[0], regimeIndex(1, false));  // no scale: one regime, the moving threshold's
  EXPECT_EQ(r[1], regimeIndex(0, false));  // a scale: at zero speed it is slow
  MovingRegimes none;
  none.reset(Eigen::VectorXd(), Eigen::VectorXd());
  EXPECT_FALSE(none.enabled());
}

TEST(MovingRegimes, EachJointIsJudgedByItsRegimesThresholdOrTheMovingOne) {
  MonitorThresholds t;
  t.values = Eigen::Vector2d(2.0, 3.0);
  Eigen::VectorXd out;
  regimeThresholds(t, Eigen::Vector2i(0, 5), out);  // without regimes: the moving thresholds
  EXPECT_EQ(out, t.values);
  t.values_by_regime = Eigen::MatrixXd::Zero(2, kMovingRegimes);
  t.values_by_regime(0, 0) = 5.0;  // slow: larger (the friction's sign)
  t.values_by_regime(0, 2) = 0.5;  // cruising: smaller
  regimeThresholds(t, Eigen::Vector2i(0, 5), out);
  EXPECT_EQ(out, Eigen::Vector2d(5.0, 3.0));  // joint 2's fast regime had too little calibration
  regimeThresholds(t, Eigen::Vector2i(2, 2), out);
  EXPECT_EQ(out, Eigen::Vector2d(0.5, 3.0));
}

}  // namespace
}  // namespace dynid
