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
  Eigen::Vector2d share{1.0, 1.0};  // each joint's share of v
  ArmState run(double seconds, double v, double r, bool hold = false) {
    ArmState s = ArmState::kMoving;
    for (int k = 0; k < static_cast<int>(seconds * 1000.0 + 0.5); ++k) {
      const Eigen::Vector2d dq(share[0] * v + 2e-4 * gauss(rng), share[1] * v + 2e-4 * gauss(rng));
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
  // Stopped: at rest once the smoothed velocity falls within the rest velocity (20 ms ln(100),
  // 92 ms), settling until it has been still kRestSettleSeconds, then settled, where the level the
  // arm holds (static friction: 3.7 N m here) is not a push.
  EXPECT_EQ(f.run(kRestSettleSeconds - 0.01, 0.0, 3.7), ArmState::kRest);
  EXPECT_TRUE(f.states.settling());
  EXPECT_EQ(f.states.statistic(), Eigen::Vector2d::Zero());  // settling, a still joint counts none
  EXPECT_EQ(f.run(0.15, 0.0, 3.7), ArmState::kRest);
  EXPECT_FALSE(f.states.settling());
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

// While the arm stirs at rest (a joint beyond its rest velocity, short of leaving rest), a change
// counts only on a joint that stirs and where it drives that joint's motion: a change against it is
// friction's, and one on a joint still held is the start's (its torque ramping into its friction).
TEST(StateResidual, WhileTheArmStirsAChangeCountsWhereItDrivesAJointsMotion) {
  Feed still, stirring, one;
  still.share = Eigen::Vector2d(0.0, 0.0);
  one.share = Eigen::Vector2d(1.0, 0.0);  // joint 1 stirs, joint 2 is held
  for (Feed* f : {&still, &stirring, &one}) {
    f->states.reset(Eigen::Vector2d(1e-3, 1e-3));
    ASSERT_EQ(f->run(1.0, 0.0, 1.0), ArmState::kRest);
  }
  // The residual changes by +0.5 on joint 1 and -0.5 on joint 2 (Feed mirrors it), the level held
  // as an event builds, at 2 rest velocities (+) where a joint stirs.
  for (Feed* f : {&still, &stirring, &one})
    ASSERT_EQ(f->run(0.3, 2e-3, 1.5, true), ArmState::kRest);
  // Still: the smallest change over the last kRestPersistSeconds, 0.5 (1 - e^(-250/80)) = 0.478;
  // 25 sigma of the smoothed noise (0.0008) is the bound.
  EXPECT_NEAR(still.states.statistic()[0], 0.478, 0.02);
  EXPECT_NEAR(still.states.statistic()[1], -0.478, 0.02);
  // Stirring: joint 1's change drives its motion and counts; joint 2's works against it.
  EXPECT_NEAR(stirring.states.statistic()[0], 0.478, 0.02);
  EXPECT_EQ(stirring.states.statistic()[1], 0.0);
  // Joint 1 stirs, joint 2 is held: joint 2's change does not count while the arm stirs.
  EXPECT_NEAR(one.states.statistic()[0], 0.478, 0.02);
  EXPECT_EQ(one.states.statistic()[1], 0.0);
}

// Settling (still for less than kRestSettleSeconds), a push that slips its joint is judged at rest:
// the change that drives the stirring joint counts, a still joint's does not.
TEST(StateResidual, SettlingAPushThatSlipsItsJointCountsAtRest) {
  Feed f;
  f.states.reset(Eigen::Vector2d(1e-3, 1e-3));
  EXPECT_EQ(f.run(1.0, 0.1, 1.0), ArmState::kMoving);
  f.run(0.15, 0.0, 1.0);  // stopped: still from about 92 ms on
  ASSERT_EQ(f.states.state(), ArmState::kRest);
  ASSERT_TRUE(f.states.settling());
  // Joint 1 slips at 2 rest velocities under +0.5 N m (joint 2, held, sees -0.5), the level held.
  f.share = Eigen::Vector2d(1.0, 0.0);
  EXPECT_EQ(f.run(0.3, 2e-3, 1.5, true), ArmState::kRest);
  EXPECT_TRUE(f.states.settling());  // stirring restarts the settling
  // 0.5 (1 - e^(-250/80)) = 0.478 on joint 1, 25 sigma of the smoothed noise the bound; none on 2.
  EXPECT_NEAR(f.states.statistic()[0], 0.478, 0.02);
  EXPECT_EQ(f.states.statistic()[1], 0.0);
}

TEST(StateResidual, ALevelStandsStillOnlySoLongAndAnEventAtRestSettlesAgain) {
  Feed f;
  f.states.reset(Eigen::Vector2d(1e-3, 1e-3));
  f.run(1.0, 0.0, 1.0);
  ASSERT_EQ(f.states.state(), ArmState::kRest);
  // A new holding level with the level held: after kRestFreezeSeconds it follows again.
  f.run(kRestFreezeSeconds + 6 * kRestBaselineSeconds, 0.0, 1.6, true);
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.02);
  // An event at rest ended: settling until still kRestSettleSeconds again, then settled at the
  // level of that moment.
  f.states.settleAgain(f.t);
  EXPECT_EQ(f.run(kRestSettleSeconds - 0.01, 0.0, 2.0), ArmState::kRest);
  EXPECT_TRUE(f.states.settling());
  EXPECT_EQ(f.run(0.2, 0.0, 2.0), ArmState::kRest);
  EXPECT_FALSE(f.states.settling());
  EXPECT_LT(f.states.statistic().cwiseAbs().maxCoeff(), 0.0125);  // as above: the noise
  // A gap (dt = 0): the observer starts again from zero, so the arm is moving until it has settled
  // (no settling state), then at rest.
  f.first = true;
  EXPECT_EQ(f.run(kRestSettleSeconds - 0.01, 0.0, 2.0), ArmState::kMoving);
  EXPECT_EQ(f.run(0.2, 0.0, 2.0), ArmState::kRest);
  EXPECT_FALSE(f.states.settling());
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
