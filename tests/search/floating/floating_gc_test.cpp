// The GC error on a floating base (search/floating/floating_gc.hpp), against inverse dynamics:
// ANYmal C hung from a force-torque sensor on its base, its joints swinging; the torques and the
// sensor's wrench are the ones floatingRnea says the motion needs, so a rollout of the true model
// driven by them follows the motion up to the inputs' zero-order hold.
#include "search/floating/floating_gc.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/floating/floating_rnea.hpp"
#include "tests/common/floating_gc_data.hpp"
#include "tests/common/floating_models.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

using test::record;
using test::sensor;
using test::suspended;

FloatingGcOptions segments() {
  FloatingGcOptions o;
  o.horizon = 0.02;
  o.num_segments = 10;
  return o;
}

TEST(FloatingGc, TheTrueModelFollowsASuspendedMotionToItsInputsHold) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcResult at_1k = floatingGcError(model, suspended(model, 1000.0, 0.5), segments());
  ASSERT_EQ(at_1k.starts.size(), 10u);
  EXPECT_EQ(at_1k.samples_per_segment, 20);
  FloatingGcOptions near = segments();
  near.horizon = 0.0203;  // the nearest whole number of periods: 20
  EXPECT_EQ(floatingGcError(model, suspended(model, 1000.0, 0.5), near).samples_per_segment, 20);
  // The torques held over each 1 ms step: dq is off by about the horizon x half the step x the
  // joints' third derivative (0.02 x 5e-4 x 0.3 (2 pi 1.6)^3 ~ 3e-3 at most), squared and summed
  // over 12 joints and 10 segments: below 1e-3 (measured 1.2e-4).
  EXPECT_LT(at_1k.error, 1e-3);
  // Halving the step halves that hold's error: the squared error falls about fourfold (measured
  // 4.0). An error in the dynamics or the sensor's wrench would not shrink with the step.
  const FloatingGcResult at_2k = floatingGcError(model, suspended(model, 2000.0, 0.5), segments());
  EXPECT_GT(at_1k.error / at_2k.error, 3.0) << at_1k.error << " then " << at_2k.error;
  EXPECT_LT(at_1k.error / at_2k.error, 5.0) << at_1k.error << " then " << at_2k.error;
}

TEST(FloatingGc, AWrongTrunkMassPredictsTheBaseFalling) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcData data = suspended(model, 1000.0, 0.5);
  const double truth = floatingGcError(model, data, segments()).error;
  FloatingModel heavier = model;
  Eigen::VectorXd theta = heavier.standardParameters();
  theta.head<10>() *= 1.1;  // the trunk 10 % heavier, its shape the same
  heavier.setStandardParameters(theta);
  const double wrong = floatingGcError(heavier, data, segments()).error;
  // The sensor carries the true weight: the heavier model's base sinks and turns, every segment
  // off by more than the truth's whole error (measured 334x the truth's sum; 100x: a margin for
  // another compiler's round-off in the truth's small error).
  EXPECT_GT(wrong, 100.0 * truth) << wrong << " against " << truth;
}

/// A base spinning about a tilted axis at 1 rad/s, the joints held still: the orientation of
/// each sample in closed form (q0 (cos(wt/2), sin(wt/2) axis), the twist in the base frame), the
/// sensor's wrench from inverse dynamics. The rollout turns the base as the twist says: a wrong
/// sign or side in the quaternion's rate would leave 2 x 0.02 rad a segment, 1.6e-3 squared.
/// A base spinning at 1 rad/s about a tilted axis, its origin moving at `velocity` (world axes,
/// constant: a uniform translation), the joints held at 0.3 rad or, with `swing`, swinging 0.2 rad
/// about it at 1.3 Hz (each joint its own phase); the sensor's wrench and the torques from inverse
/// dynamics; 0.3 s at 1 kHz.
FloatingGcData spinning(const FloatingModel& model, const Eigen::Vector3d& velocity,
                        bool swing = false) {
  const int n = model.numJoints(), samples = 301;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector4d q0 = Eigen::Vector4d(0.9, 0.1, 0.3, -0.2).normalized();
  FloatingGcData d;
  d.contacts = {sensor()};
  d.time.resize(samples);
  d.orientation.resize(4, samples);
  d.twist.setZero(6, samples);
  d.q = Eigen::MatrixXd::Constant(n, samples, 0.3), d.dq.setZero(n, samples);
  d.tau.resize(n, samples);
  d.wrenches = {Eigen::MatrixXd(6, samples)};
  FloatingData data(model);
  for (int k = 0; k < samples; ++k) {
    const double t = k / 1000.0;
    Eigen::Vector4d spin;
    spin << std::cos(0.5 * t), std::sin(0.5 * t) * axis;
    // q0 spin, the product written out (w, x, y, z).
    Eigen::Vector4d q;
    q[0] = q0[0] * spin[0] - q0.tail<3>().dot(spin.tail<3>());
    q.tail<3>() = q0[0] * spin.tail<3>() + spin[0] * q0.tail<3>() +
                  cross(Eigen::Vector3d(q0.tail<3>()), Eigen::Vector3d(spin.tail<3>()));
    d.time[k] = t;
    d.orientation.col(k) = q;
    Eigen::VectorXd ddq = Eigen::VectorXd::Zero(n);
    for (int j = 0; swing && j < n; ++j) {
      const double w = 2.0 * M_PI * 1.3, phase = w * t + j;
      d.q(j, k) = 0.3 + 0.2 * std::sin(phase);
      d.dq(j, k) = 0.2 * w * std::cos(phase);
      ddq[j] = -0.2 * w * w * std::sin(phase);
    }
    BaseMotion base;
    base.rotation = baseRotation(q);
    const Eigen::Vector3d v = base.rotation.transpose() * velocity;
    d.twist.col(k) << axis, v;
    base.twist = d.twist.col(k);
    base.acceleration << Eigen::Vector3d::Zero(), -cross(axis, v);  // d/dt R^T V
    record(d, k, floatingRnea(model, data, base, d.q.col(k), d.dq.col(k), ddq));
  }
  return d;
}

TEST(FloatingGc, ASpinningBaseTurnsAsItsTwistSays) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcResult r =
      floatingGcError(model, spinning(model, Eigen::Vector3d::Zero()), segments());
  // Gravity turns in the base frame at 1 rad/s, so the sensor's wrench changes: the hold's error
  // (measured 7.9e-8) against 1.0e-3 with the twist taken in world axes (measured, the only test
  // here a rotation mistake fails: the others' bases barely turn).
  EXPECT_LT(r.error, 1e-5) << r.error;
}

/// The base's linear velocity turns with the base (a uniform translation seen in its frame); where
/// a dataset does not record it (an IMU's: zero), the rollout of everything else is the same.
TEST(FloatingGc, ATranslatingBaseNeedsNoLinearVelocityForTheRest) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  FloatingGcData moving = spinning(model, Eigen::Vector3d(0.8, -0.5, 0.3), true);
  // The base frame turns at 1 rad/s, so its v turns too; the joints swing: the hold's error.
  EXPECT_LT(floatingGcError(model, moving, segments()).error, 1e-4);
  moving.linear_velocity = false;
  FloatingGcData unrecorded = moving;
  unrecorded.twist.bottomRows<3>().setZero();
  const double with = floatingGcError(model, moving, segments()).error;
  const double without = floatingGcError(model, unrecorded, segments()).error;
  // The joints' and the rotation's dynamics do not depend on a uniform translation: the two
  // differ by round-off in the RK4 sums (1e-9 relative, far above it, far below any model's).
  EXPECT_GT(with, 1e-9);  // the swinging joints' hold: an error round-off does not make
  EXPECT_NEAR(without, with, 1e-9 * with) << with;
}

/// A candidate far from physical (a trunk of negative rotational inertia: its mass matrix not
/// positive definite) diverges or throws inside the dynamics: each such segment counts as the cap,
/// and the call still returns.
TEST(FloatingGc, ADivergingCandidateCountsAsTheCap) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  FloatingModel wrong = model;
  Eigen::VectorXd theta = wrong.standardParameters();
  theta.segment<6>(4) *= -1.0;  // Ixx .. Izz
  wrong.setStandardParameters(theta);
  const FloatingGcResult r = floatingGcError(wrong, suspended(model, 1000.0, 0.5), segments());
  EXPECT_EQ(r.segment_errors.maxCoeff(), kMaxSegmentError) << r.segment_errors.transpose();
}

/// The suspended motion's sensor known by its flag alone: the rollout holds the base still by
/// whatever forces it takes, and the joints follow their torques as with the wrench measured; a
/// flag that says the sensor let go drops the base.
TEST(FloatingGc, AFlaggedContactHoldsWhereItsFlagSays) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcData measured = suspended(model, 1000.0, 0.5);
  FloatingGcData flagged = measured;
  flagged.wrenches = {Eigen::MatrixXd()};
  flagged.flags = {std::vector<char>(static_cast<std::size_t>(measured.time.size()), 1)};
  const double with_wrench = floatingGcError(model, measured, segments()).error;
  const double held = floatingGcError(model, flagged, segments()).error;
  // Measured 1.16e-4 with the wrench and 1.20e-4 held: the inputs' 1 ms hold either way.
  EXPECT_LT(held, 2.0 * with_wrench) << held << " against " << with_wrench;
  // The legs 10 % heavier: their own dynamics, which the held base does not hide (measured 0.144,
  // 1200 times).
  FloatingModel heavier = model;
  Eigen::VectorXd theta = heavier.standardParameters();
  theta.segment(kLinkParameterCount, 10 * model.numJoints()) *= 1.1;
  heavier.setStandardParameters(theta);
  const double wrong = floatingGcError(heavier, flagged, segments()).error;
  EXPECT_GT(wrong, 10.0 * held) << wrong << " against " << held;
  // Let go: the base falls and turns, reaching 0.2 m/s in 20 ms, the legs swinging it (measured
  // 51).
  flagged.flags[0].assign(flagged.flags[0].size(), 0);
  EXPECT_GT(floatingGcError(model, flagged, segments()).error, 0.1);
  flagged.flags[0].pop_back();
  try {
    floatingGcError(model, flagged, segments());
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "`flags`")) << e.what();
  }
}

/// A recording with a gap (a stall in the stamps, a log split): no segment spans it, and every
/// one still follows the motion.
TEST(FloatingGc, NoSegmentCrossesAGap) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcData whole = suspended(model, 1000.0, 0.3);
  // Samples 100-159 dropped: 61 ms between samples 99 and 160.
  std::vector<int> kept;
  for (int k = 0; k < whole.time.size(); ++k)
    if (k < 100 || k >= 160) kept.push_back(k);
  FloatingGcData d = whole;
  const auto keep = [&](const auto& m) {
    Eigen::MatrixXd out(m.rows(), static_cast<Eigen::Index>(kept.size()));
    for (std::size_t j = 0; j < kept.size(); ++j)
      out.col(static_cast<Eigen::Index>(j)) = m.col(kept[j]);
    return out;
  };
  d.time = keep(whole.time.transpose()).transpose();
  d.orientation = keep(whole.orientation);
  d.twist = keep(whole.twist);
  d.q = keep(whole.q), d.dq = keep(whole.dq), d.tau = keep(whole.tau);
  d.wrenches = {keep(whole.wrenches[0])};
  FloatingGcOptions every = segments();
  every.num_segments = 0;
  const FloatingGcResult r = floatingGcError(model, d, every);
  // 100 samples before the gap hold four segments of 20 steps (the fifth would end at sample
  // 100), the 141 after it seven.
  EXPECT_EQ(r.starts.size(), 11u);
  for (int start : r.starts)
    EXPECT_NEAR(d.time[start + r.samples_per_segment] - d.time[start], 0.02, 1e-9) << start;
  EXPECT_LT(r.error, 1e-3);  // as the whole recording's (the hold's error)
}

TEST(FloatingGc, RefusesWhatItCannotRollOut) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcData data = suspended(model, 1000.0, 0.05);
  const auto refused = [&](FloatingGcData d, FloatingGcOptions o, const char* field) {
    try {
      floatingGcError(model, d, o);
      ADD_FAILURE() << field << ": not refused";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  FloatingGcOptions o = segments();
  o.horizon = 0.0004;  // under half a 1 ms period
  refused(data, o, "`horizon`");
  o.horizon = 0.1;  // longer than the 50 ms recorded
  refused(data, o, "`horizon`");
  o = segments();
  o.substeps = 100000;  // 20 periods x 1e5 steps: past the 1e6 steps a segment may take
  refused(data, o, "`substeps`");
  FloatingGcData d = data;
  d.tau.conservativeResize(d.tau.rows() - 1, Eigen::NoChange);
  refused(d, segments(), "`tau`");
  d = data;
  d.wrenches[0].conservativeResize(3, Eigen::NoChange);  // a frame's wrench has six rows
  refused(d, segments(), "`wrenches`");
  d = data;
  d.time[3] = d.time[2];
  refused(d, segments(), "`time`");
}

}  // namespace
}  // namespace dynid
