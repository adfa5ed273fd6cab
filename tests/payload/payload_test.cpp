#include "analysis/payload/payload.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/LU>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "tests/common/payload_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::payloadLog;
using test::payloadMotion;
using test::toolBody;
using test::withPayload;

Pose<double> flange() { return test::pumaFlange(); }

/// Short names for the helpers of tests/common/payload_logs.hpp.
Trajectory motion(const Model& model, double seconds, double rate, std::vector<int> still = {}) {
  return payloadMotion(model, seconds, rate, still);
}
std::string logOf(const Model& model, Trajectory t, const std::string& name, double noise = 0.0,
                  std::uint64_t seed = 1, Eigen::VectorXd gain = {}) {
  return payloadLog(model, std::move(t), name, noise, seed, std::move(gain));
}

TEST(Payload, NoiseFreeTorquesGiveThePayloadInItsOwnFrame) {
  const Model arm = makePuma560(false);
  const Trajectory t = motion(arm, 10.0, 200.0);
  PayloadRequest request;
  request.arm = arm;
  request.tool = flange();
  request.data_file = logOf(withPayload(arm, 5, request.tool, toolBody()), t, "payload_exact.csv");
  const PayloadOutcome out = payloadRun(request);
  // Exact data: the least-squares body is the truth to round-off of the CSV's 17 digits and the
  // QR (1e-9 relative), and the consistent one equals it (the truth is well inside).
  EXPECT_LT((out.least_squares - toolBody()).norm(), 1e-8 * toolBody().norm());
  EXPECT_LT((out.standard - toolBody()).norm(), 1e-6 * toolBody().norm());
  EXPECT_NEAR(out.mass, 1.2, 1e-8);
  EXPECT_LT((out.com - Eigen::Vector3d(0.03, -0.02, 0.08)).norm(), 1e-8);
  EXPECT_TRUE(out.unseen.empty());
  EXPECT_EQ(out.mode, "single");
  EXPECT_EQ(out.link_name, arm.link_names[5]);
  for (const PayloadQuantity& q : out.quantities) EXPECT_TRUE(q.determined) << q.name;
}

TEST(Payload, IntervalsCoverTheTruthAtTheirLevel) {
  // 40 noise seeds: the 95 % intervals of the mass and the centre of mass cover the truth in at
  // least 32 (binomial(40, 0.95) falls below 33 with probability 0.3 %).
  const Model arm = makePuma560(false);
  const Trajectory t = motion(arm, 6.0, 200.0);
  const Model loaded = withPayload(arm, 5, flange(), toolBody());
  int covered = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    PayloadRequest request;
    request.arm = arm;
    request.tool = flange();
    request.data_file = logOf(loaded, t, "payload_noise.csv", 0.2, seed);
    const PayloadOutcome out = payloadRun(request);
    const Eigen::Vector4d truth(1.2, 0.03, -0.02, 0.08);
    for (int k = 0; k < 4; ++k, ++total)
      covered += std::abs(out.quantities[k].value - truth[k]) <= out.quantities[k].half_width;
  }
  EXPECT_GE(covered, 32 * 4);
  EXPECT_LE(covered, total);
}

TEST(Payload, TheUnloadedRunCancelsWhatTheArmModelGetsWrong) {
  const Model truth = makePuma560(false);
  Model wrong = truth;  // the arm model: link 3's mass 10 % off
  RigidInertia<double> i3 = truth.inertias()[2];
  i3.mass *= 1.1;
  wrong.setLinkInertia(2, i3);
  const Trajectory t = motion(truth, 10.0, 200.0);
  // The unloaded run starts 0.25 s later in its log (the pair is aligned by its positions).
  Trajectory later = motion(truth, 10.25, 200.0);
  Trajectory shifted = later.samples(0, later.numSamples());
  {
    const Trajectory head = motion(truth, 10.0, 200.0);
    shifted.q.rightCols(head.numSamples()) = head.q;
    shifted.dq.rightCols(head.numSamples()) = head.dq;
    shifted.ddq.rightCols(head.numSamples()) = head.ddq;
    for (int k = 0; k < 50; ++k) {
      shifted.q.col(k) = head.q.col(0);
      shifted.dq.col(k).setZero();
      shifted.ddq.col(k).setZero();
    }
  }
  PayloadRequest request;
  request.arm = wrong;
  request.tool = flange();
  request.data_file = logOf(withPayload(truth, 5, flange(), toolBody()), t, "payload_loaded.csv");
  const PayloadOutcome single = payloadRun(request);
  request.unloaded_file = logOf(truth, shifted, "payload_unloaded.csv");
  const PayloadOutcome difference = payloadRun(request);
  EXPECT_EQ(difference.mode, "difference");
  EXPECT_NEAR(difference.shift, 0.25, 1e-9);
  EXPECT_LT(difference.motion_difference.maxCoeff(), 1e-12);
  EXPECT_NEAR(difference.mass, 1.2, 1e-6);
  EXPECT_GT(std::abs(single.mass - 1.2), 100.0 * std::abs(difference.mass - 1.2));
}

/// The PUMA with its friction (it cancels in the difference) carrying the tool in the loaded run
/// (motion `loaded`) and not in the unloaded one (`unloaded`), torques measured through
/// constants off by these gains (measured = true / gain); drive gains from the known 1.2 kg.
const Eigen::VectorXd kGains = (Eigen::VectorXd(6) << 1.05, 0.97, 1.1, 0.92, 1.0, 1.03).finished();
PayloadOutcome gainsRun(const Trajectory& loaded, const Trajectory& unloaded,
                        const std::string& name) {
  const Model arm = makePuma560(true);
  PayloadRequest request;
  request.arm = arm;
  request.tool = flange();
  request.known_mass = 1.2;
  request.data_file = logOf(withPayload(arm, 5, flange(), toolBody()), loaded, name + "_loaded.csv",
                            0.0, 1, kGains);
  request.unloaded_file = logOf(arm, unloaded, name + "_unloaded.csv", 0.0, 1, kGains);
  return payloadRun(request);
}

TEST(Payload, DriveGainsFromAKnownMass) {
  const Trajectory t = motion(makePuma560(true), 10.0, 200.0);
  const PayloadOutcome out = gainsRun(t, t, "gain");
  ASSERT_TRUE(out.gains.has_value());
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(out.gains->scale[j], kGains[j], 1e-6 * kGains[j]) << j;
    EXPECT_TRUE(out.gains->determined[j]) << j;
  }
}

// The load changes the tracking: the unloaded run's motion differs from the loaded one's by a
// smooth 10 mrad. The measured difference scales the arm's own torque difference too, so the
// gains are still exact (they came out 1 % to 9 % off when that difference was left unscaled).
TEST(Payload, DriveGainsHoldWhenTheLoadChangesTheTracking) {
  const Trajectory t = motion(makePuma560(true), 10.0, 200.0);
  Trajectory other = t;
  for (int k = 0; k < t.numSamples(); ++k)
    for (int j = 0; j < 6; ++j) {
      const double w = 2.0 * std::numbers::pi * (0.3 + 0.1 * j), phase = w * t.time[k] + j;
      other.q(j, k) += 0.01 * std::sin(phase);
      other.dq(j, k) += 0.01 * w * std::cos(phase);
      other.ddq(j, k) -= 0.01 * w * w * std::sin(phase);
    }
  const PayloadOutcome out = gainsRun(t, other, "gain_track");
  ASSERT_TRUE(out.gains.has_value());
  EXPECT_GT(out.motion_difference.maxCoeff(), 0.005);  // the motions do differ
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(out.gains->scale[j], kGains[j], 1e-6 * kGains[j]) << j;  // exact data
}

TEST(Payload, AWristThatDoesNotTurnLeavesCombinationsUnseenAndSaysSo) {
  // Only joint 1 moves (the PUMA's vertical axis): the payload turns about one axis, and most of
  // its centre of mass and inertia is seen only in combinations.
  const Model arm = makePuma560(false);
  const Trajectory t = motion(arm, 10.0, 200.0, {1, 2, 3, 4, 5});
  PayloadRequest request;
  request.arm = arm;
  request.tool = flange();
  request.data_file =
      logOf(withPayload(arm, 5, flange(), toolBody()), t, "payload_still.csv", 0.01, 3);
  const PayloadOutcome out = payloadRun(request);
  EXPECT_FALSE(out.unseen.empty());
  bool some_inertia_undetermined = false;
  for (const PayloadQuantity& q : out.quantities)
    if (q.group == "principal moments" && !q.determined) some_inertia_undetermined = true;
  EXPECT_TRUE(some_inertia_undetermined);
  ASSERT_FALSE(out.advice.empty());
  EXPECT_NE(out.advice.back().find("rotate the wrist more, joint 4"), std::string::npos)
      << out.advice.back();
  // The mass is still determined, and the body consistent.
  EXPECT_TRUE(out.quantities[0].determined);
  EXPECT_NEAR(out.mass, 1.2, 0.01);
  EXPECT_GE(out.principal_moments.minCoeff(), 0.0);
}

TEST(Payload, FrictionReestimatedWithThePayload) {
  Model arm = makePuma560(true);
  Model loaded = withPayload(arm, 5, flange(), toolBody());
  DriveParameters<double> d = loaded.drives()[1];
  d[DriveTerm::kViscous] += 0.5;  // the load raises joint 2's viscous friction
  loaded.setDrive(1, d);
  const Trajectory t = motion(arm, 10.0, 200.0);
  PayloadRequest request;
  request.arm = arm;
  request.tool = flange();
  request.refit_friction = true;
  request.data_file = logOf(loaded, t, "payload_friction.csv");
  const PayloadOutcome out = payloadRun(request);
  bool found = false;
  for (const FrictionChange& c : out.friction)
    if (c.name == "Fv2") {
      found = true;
      EXPECT_NEAR(c.with_payload - c.arm, 0.5, 1e-6);
    }
  EXPECT_TRUE(found);
  EXPECT_LT((out.standard - toolBody()).norm(), 1e-5 * toolBody().norm());
}

TEST(Payload, RefusesWhatItCannotUse) {
  const Model arm = makePuma560(false);
  const Trajectory t = motion(arm, 4.0, 200.0);
  const std::string loaded = logOf(withPayload(arm, 5, flange(), toolBody()), t, "refuse.csv");
  PayloadRequest base;
  base.arm = arm;
  base.data_file = loaded;
  {
    PayloadRequest r = base;
    r.link = "no_such_link";
    EXPECT_THROW(payloadRun(r), InputError);
  }
  {
    PayloadRequest r = base;
    r.known_mass = 0.0;
    r.unloaded_file = loaded;
    EXPECT_THROW(payloadRun(r), InputError);
  }
  {
    PayloadRequest r = base;  // a log of a 7-joint robot
    r.data_file = logOf(makePanda(false), motion(makePanda(false), 2.0, 100.0), "refuse_panda.csv");
    EXPECT_THROW(payloadRun(r), Error);
  }
  {
    PayloadRequest r = base;  // the torques in mN m
    Trajectory scaled = t;
    r.data_file = logOf(withPayload(arm, 5, flange(), toolBody()), t, "refuse_units.csv", 0.01);
    const Trajectory read = readDatasetCsv(r.data_file, 6);
    scaled.tau = read.tau * 1000.0;
    r.data_file = test::tempPath("refuse_units_mnm.csv");
    writeDatasetCsv(r.data_file, scaled);
    EXPECT_THROW(payloadRun(r), InputError);
  }
  {
    PayloadRequest r = base;  // a heavier robot of the same joints: said, not silently fitted
    Model other = makePuma560(false);
    for (int i = 0; i < 6; ++i) {
      RigidInertia<double> inertia = other.inertias()[i];
      inertia.mass *= 4.0;
      inertia.first_moment *= 4.0;
      inertia.inertia *= 4.0;
      other.setLinkInertia(i, inertia);
    }
    r.data_file = logOf(other, t, "refuse_other.csv", 0.01);
    const PayloadOutcome out = payloadRun(r);
    ASSERT_FALSE(out.warnings.empty());
    EXPECT_NE(out.warnings[0].find("more than half the arm"), std::string::npos) << out.warnings[0];
  }
  {
    PayloadRequest r = base;  // a pair whose motions differ
    Trajectory other = motion(arm, 4.0, 200.0);
    other.q *= 1.5;
    other.dq *= 1.5;
    other.ddq *= 1.5;
    r.unloaded_file = logOf(arm, other, "refuse_pair.csv");
    try {
      payloadRun(r);
      ADD_FAILURE() << "a pair of different motions was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("same commanded motion"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("`max_motion_difference`"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace dynid
