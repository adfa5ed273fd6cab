#include "analysis/estimation/reversals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace dynid {
namespace {

/// Three joints over 1000 samples of three sine periods of velocity: joint 1's residual is 1 N m
/// within a tenth of its RMS speed of zero velocity and 0.05 N m elsewhere, joint 2's is 0.05 N m
/// everywhere, and joint 3 never moves.
Prediction constructed() {
  const int count = 1000;
  Prediction p;
  p.velocity.setZero(3, count);
  p.measured.setZero(3, count);
  p.predicted.setZero(3, count);
  const double rms = 0.7 / std::sqrt(2.0);  // of 0.7 sin over whole periods
  for (int k = 0; k < count; ++k) {
    const double dq = 0.7 * std::sin(2.0 * std::numbers::pi * 3.0 * k / count);
    p.velocity(0, k) = p.velocity(1, k) = dq;
    p.measured(0, k) = std::abs(dq) < 0.1 * rms ? 1.0 : 0.05;
    p.measured(1, k) = 0.05;
    p.measured(2, k) = 0.05;
  }
  return p;
}

TEST(Reversals, FlagsAResidualGatheredNearZeroVelocityAndNothingSpreadEvenly) {
  const Prediction p = constructed();
  const ReversalResidual r = reversalResidual(p);
  ASSERT_EQ(r.samples, 1000);
  // The band and the shares, counted here independently.
  int in_band = 0;
  double inside = 0.0, total = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double e = p.measured(0, k) * p.measured(0, k);
    total += e;
    if (std::abs(p.velocity(0, k)) < r.speed[0]) ++in_band, inside += e;
  }
  EXPECT_NEAR(r.speed[0], 0.1 * 0.7 / std::sqrt(2.0), 1e-3);  // whole periods: rms = 0.7/sqrt 2
  EXPECT_EQ(r.sample_share[0], in_band / 1000.0);
  EXPECT_DOUBLE_EQ(r.residual_share[0], inside / total);
  // About 4.5 % of a sine's samples lie within 0.071 of its amplitude's zero crossings, and they
  // hold (1/0.05)^2 = 400 times the others' squared residual: about 95 % of it.
  EXPECT_GT(r.residual_share[0], 0.9);
  EXPECT_LT(r.sample_share[0], 0.06);
  // An even residual: its share is the samples' share (to the round-off of 1000 summed squares).
  EXPECT_NEAR(r.residual_share[1], r.sample_share[1], 1e-12);
  // A joint at rest has no band and no share.
  EXPECT_EQ(r.speed[2], 0.0);
  EXPECT_EQ(r.sample_share[2], 0.0);
  EXPECT_EQ(r.residual_share[2], 0.0);
  EXPECT_EQ(r.flagged, std::vector<int>{0});
}

/// Joint 1's residual within the band set to `level` (0.05 N m elsewhere).
ReversalResidual withBandResidual(double level) {
  Prediction p = constructed();
  for (int k = 0; k < 1000; ++k)
    if (p.measured(0, k) == 1.0) p.measured(0, k) = level;
  return reversalResidual(p);
}

TEST(Reversals, NeedsBothMarks) {
  // About 4.5 % of the samples in the band. At 0.15 N m (9 times the others' squared residual)
  // the band holds about 30 %: flagged.
  EXPECT_EQ(withBandResidual(0.15).flagged, std::vector<int>{0});
  // At 0.12 N m (5.8 times) about 21 %: concentrated (over 4 times the sample share) but under
  // the 25 % mark.
  const ReversalResidual low = withBandResidual(0.12);
  EXPECT_LT(low.residual_share[0], kReversalResidualShare);
  EXPECT_GE(low.residual_share[0], kReversalConcentration * low.sample_share[0]);
  EXPECT_TRUE(low.flagged.empty());
  // A joint at rest on 30 % of the samples with an even residual: 30 % of it in the band, over
  // the 25 % mark, but no more concentrated than the samples: not flagged.
  Prediction rest = constructed();
  for (int k = 0; k < 300; ++k) rest.velocity(1, k) = 0.0;
  const ReversalResidual r = reversalResidual(rest);
  EXPECT_GE(r.residual_share[1], kReversalResidualShare);
  EXPECT_LT(r.residual_share[1], kReversalConcentration * r.sample_share[1]);
  EXPECT_EQ(r.flagged, std::vector<int>{0});
  // Without velocities (a prediction made without them): nothing measured.
  rest.velocity.resize(0, 0);
  EXPECT_EQ(reversalResidual(rest).samples, 0);
}

// A residual shaped like the friction the model lacks (0.3 sign(dq) + 0.2 dq - 0.1, plus a
// small even part) is explained almost wholly by that fit; an even residual that alternates in
// sign from sample to sample, hardly at all (3 columns fitted to 1000 samples).
TEST(Reversals, MeasuresHowMuchOfTheResidualHasFrictionsShape) {
  Prediction p = constructed();
  for (int k = 0; k < 1000; ++k) {
    const double dq = p.velocity(0, k);
    p.measured(0, k) = 0.3 * (dq > 0.0   ? 1.0
                              : dq < 0.0 ? -1.0
                                         : 0.0) +
                       0.2 * dq - 0.1 + (k % 2 == 0 ? 0.01 : -0.01);
    p.measured(1, k) = k % 2 == 0 ? 0.05 : -0.05;
  }
  const ReversalResidual r = reversalResidual(p);
  ASSERT_EQ(r.friction_share.size(), 3);
  // What the fit leaves is the even part, 0.01^2 against a mean square near 0.3^2 + 0.1^2 + ...
  EXPECT_GT(r.friction_share[0], 0.99);
  EXPECT_LT(r.friction_share[1], 0.01);
  // Joint 3 (at rest, a constant 0.05 N m residual) is an offset: Fo's shape.
  EXPECT_GT(r.friction_share[2], 0.99);
  EXPECT_EQ(r.friction_flagged, (std::vector<int>{0, 2}));
}

// Noise-free data leave round-off (a held-out error of 5e-14 %): however friction-shaped, it is
// not flagged; the same shape at 1e-3 of the torque is.
TEST(Reversals, RoundOffIsNotFriction) {
  Prediction p = constructed();
  const Eigen::MatrixXd shape = p.measured;  // joint 1's friction-shaped residual, as above
  p.predicted = Eigen::MatrixXd::Constant(3, shape.cols(), 20.0);  // a 20 N m torque
  p.measured = p.predicted + 1e-12 * shape;  // 1e-14 of the torque (5e-14 N m: 14 ulps of 20)
  const ReversalResidual quiet = reversalResidual(p);
  EXPECT_GT(quiet.residual_share[0], 0.9);  // the shape is there
  EXPECT_TRUE(quiet.flagged.empty());
  EXPECT_TRUE(quiet.friction_flagged.empty());
  p.measured = p.predicted + 1e-3 * shape;
  EXPECT_EQ(reversalResidual(p).flagged, std::vector<int>{0});
}

}  // namespace
}  // namespace dynid
