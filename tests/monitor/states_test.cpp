// The monitor's arm states (analysis/monitor/states.hpp): when the arm is at rest, and the change
// from the level at rest that it is judged by there.
#include "analysis/monitor/states.hpp"

#include <gtest/gtest.h>

#include <random>

namespace dynid {
namespace {

/// Feeds samples at 1 kHz: velocity `v` plus white noise, residual `r` plus white noise.
struct Feed {
  StateResidual states;
  std::mt19937_64 rng{11};
  std::normal_distribution<double> gauss{0.0, 1.0};
  double t = 0.0;
  bool first = true;
  ArmState run(double seconds, double v, double r, bool hold = false) {
    ArmState s = ArmState::kMoving;
    for (int k = 0; k < static_cast<int>(seconds * 1000.0 + 0.5); ++k) {
      const Eigen::Vector2d dq(v + 2e-4 * gauss(rng), v + 2e-4 * gauss(rng));
      const Eigen::Vector2d res(r + 0.01 * gauss(rng), -r + 0.01 * gauss(rng));
      s = states.update(t, first ? 0.0 : 1e-3, res, dq, hold);
      first = false;
      t += 1e-3;
    }
    return s;
  }
};

TEST(StateResidual, AtRestAPushIsTheChangeFromTheLevelTheArmHeld) {
  Feed f;
  f.states.reset(Eigen::Vector2d(1e-3, 1e-3));  // 5 sigma of the velocity noise
  // Moving: the statistic is the residual itself.
  EXPECT_EQ(f.run(1.0, 0.1, 3.0), ArmState::kMoving);
  EXPECT_NEAR(f.states.statistic()[0], 3.0, 0.05);  // 5 sigma of the residual noise
  // Stopped: still moving until the arm has been still kRestSettleSeconds (from when the smoothed
  // velocity fell within the rest velocity: 20 ms ln(100), 92 ms), then at rest, where the level
  // the arm holds (static friction: 3.7 N m here) is not a push.
  EXPECT_EQ(f.run(kRestSettleSeconds - 0.01, 0.0, 3.7), ArmState::kMoving);
  EXPECT_EQ(f.run(0.15, 0.0, 3.7), ArmState::kRest);
  EXPECT_EQ(f.run(1.0, 0.0, 3.7), ArmState::kRest);
  // The level the arm holds is taken away: what is left is the smoothed noise (0.01 sqrt(1 ms /
  // 160 ms) = 0.0008; the bound is 15 of those, and 1/56 of the 0.7 N m a wrong level leaves).
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.0125);
  // A push of 0.5 N m: the change reaches it (the level stands still while it builds).
  f.run(0.6, 0.0, 4.2, true);
  EXPECT_NEAR(f.states.statistic()[0], 0.5, 0.015);
  EXPECT_NEAR(f.states.statistic()[1], -0.5, 0.015);
  // Without standing still, the level follows the new value within a few time constants.
  f.run(6 * kRestBaselineSeconds, 0.0, 4.2);
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.02);
  // A commanded motion leaves rest at once (kRestExitFactor rest velocities, smoothed over 20 ms).
  EXPECT_EQ(f.run(0.01, 0.1, 4.2), ArmState::kMoving);
}

TEST(StateResidual, ALevelStandsStillOnlySoLongAndAnEventAtRestSettlesAgain) {
  Feed f;
  f.states.reset(Eigen::Vector2d(1e-3, 1e-3));
  f.run(1.0, 0.0, 1.0);
  ASSERT_EQ(f.states.state(), ArmState::kRest);
  // A new holding level with the level held: after kRestFreezeSeconds it follows again.
  f.run(kRestFreezeSeconds + 6 * kRestBaselineSeconds, 0.0, 1.6, true);
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.02);
  // An event at rest ended: moving until still kRestSettleSeconds again, then at rest at the level
  // of that moment.
  f.states.settleAgain(f.t);
  EXPECT_EQ(f.run(kRestSettleSeconds - 0.01, 0.0, 2.0), ArmState::kMoving);
  EXPECT_EQ(f.run(0.2, 0.0, 2.0), ArmState::kRest);
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.0125);  // as above: the noise
  // A gap (dt = 0): moving until it settles.
  f.first = true;
  EXPECT_EQ(f.run(0.1, 0.0, 2.0), ArmState::kMoving);
  // Without rest velocities there is no rest state.
  StateResidual none;
  none.reset(Eigen::VectorXd());
  const Eigen::Vector2d r(0.3, 0.4), zero = Eigen::Vector2d::Zero();
  for (int k = 0; k < 2000; ++k)
    EXPECT_EQ(none.update(k * 1e-3, 1e-3, r, zero, false), ArmState::kMoving);
  EXPECT_EQ(none.statistic(), r);
}

}  // namespace
}  // namespace dynid
