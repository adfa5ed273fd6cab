// A standing robot's sway designed for identification (analysis/floating/standing_design.hpp):
// ANYmal C on its four feet, knees bent.
#include "analysis/floating/standing_design.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "analysis/floating/simulate.hpp"
#include "analysis/floating/standing.hpp"
#include "core/errors.hpp"
#include "tests/common/floating_datasets.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

StandingDesignRequest anymalDesign(const FloatingModel& model) {
  StandingDesignRequest r;
  r.contacts = contactsOf(model, test::kAnymalExample.contacts);
  r.stance = test::anymalKneesBent();
  r.friction_cone = 0.6;
  r.starts = 2;
  r.evaluations = 150;
  return r;
}

/// The design's motion at 100 Hz over one period, as `dynid simulate --trajectory` makes it.
std::shared_ptr<FloatingDataset> motionOf(const FloatingModel& model,
                                          const StandingDesignRequest& request,
                                          const StandingDesign& design) {
  StandingMotionRequest r;
  r.contacts = request.contacts;
  r.stance = request.stance;
  r.base_design = design.base;
  r.rate = 100.0;
  r.samples = static_cast<int>(design.base.period * r.rate);
  return standingMotion(model, r);
}

TEST(StandingDesign, DeterminesWhatASwayCanWithinItsBoundsAndTheCones) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const StandingDesignRequest request = anymalDesign(model);
  const StandingDesign design = designStandingSway(model, request);
  ASSERT_EQ(design.scores.size(), 3u);
  ASSERT_EQ(design.baseline.size(), 3u) << design.baseline_problem;
  for (std::size_t s = 0; s < 3; ++s) {
    const StandingSetScore& d = design.scores[s];
    const char* name = sensorSetName(d.set);
    // A sway determines at most what holding states do, and the design all that any sway of the
    // stance can (measured 93, 94 and 90 of 94: four feet fixed in the world tie the legs to the
    // base, and the flags' projection loses four more).
    EXPECT_LE(d.standing, d.holding) << name;
    EXPECT_EQ(d.determined, d.standing) << name;
    EXPECT_TRUE(std::isfinite(d.condition)) << name;
    // simulate --stance's default sway (one turn axis) determines fewer in every set (measured
    // 90, 91 and 87).
    EXPECT_LT(design.baseline[s].determined, d.determined) << name;
    EXPECT_FALSE(std::isfinite(design.baseline[s].condition)) << name;
  }
  EXPECT_LE(design.largest_sway, request.max_sway);
  EXPECT_LE(design.largest_turn, request.max_turn);
  EXPECT_GE(design.joint_clearance, request.joint_margin);
  EXPECT_LE(design.cone_use, 1.0);
  // At rest at the stance at t = 0, and back there after one period (to round-off of the
  // coefficients' sums).
  Eigen::VectorXd c, dc, ddc;
  for (const double t : {0.0, design.base.period}) {
    evaluateReference(design.base, t, c, dc, ddc);
    EXPECT_LT(c.lpNorm<Eigen::Infinity>(), 1e-12) << t;
    EXPECT_LT(dc.lpNorm<Eigen::Infinity>(), 1e-12) << t;
    EXPECT_LT(ddc.lpNorm<Eigen::Infinity>(), 1e-12) << t;
  }
  // simulate with the cones: every sample's forces within them at the first split, none held
  // by forces that leave them, none that the feet cannot carry.
  FloatingSimulationOptions options;
  options.contacts = request.contacts;
  options.motion_from = motionOf(model, request, design);
  options.samples = options.motion_from->numSamples();
  options.friction_cone = request.friction_cone;
  std::vector<int> outside, unsupported;
  simulateFloatingDataset(model, options, nullptr, &outside, &unsupported);
  EXPECT_TRUE(outside.empty()) << outside.size() << " samples outside the cones";
  EXPECT_TRUE(unsupported.empty());
}

/// Romeo on its two soles, the arms held at the stance: every centre of pressure kept in a
/// 0.2 x 0.1 m sole by the least-norm split, so that simulate's corner forces find it there.
TEST(StandingDesign, KeepsAHumanoidsCentresOfPressureInItsSoles) {
  const FloatingModel model = test::loadExample(test::kRomeoExample);
  StandingDesignRequest request;
  request.contacts = contactsOf(model, {"l_sole:frame", "r_sole:frame"});
  request.stance = Eigen::VectorXd::Zero(31);
  request.stance.head<12>() << 0, 0, -0.4, 0.8, -0.4, 0, 0, 0, -0.4, 0.8, -0.4, 0;  // knees bent
  request.stance.segment<7>(17) << 1.5, 0.2, -0.5, -0.5, 0, 0, 0;  // the arms down, elbows
  request.stance.segment<7>(24) << 1.5, -0.2, 0.5, 0.5, 0, 0, 0;   // off their limits
  request.friction_cone = 0.8;
  request.sole = rectangularSole(0.2, 0.1);
  request.joint_margin = 0.02;  // the ankles' roll limits are near at this stance
  request.max_swing = 0.0;      // the arms stay (moving them: 100 more variables to search)
  request.starts = 1;
  request.evaluations = 100;
  const StandingDesign design = designStandingSway(model, request);
  EXPECT_GE(design.sole_clearance, 0.0);
  EXPECT_LE(design.cone_use, 1.0);
  // What the design determines is what any sway of the stance does (measured 89, 225 and 223 of
  // 227), more than the default sway (86, 165, 163).
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_EQ(design.scores[s].determined, design.scores[s].standing);
    EXPECT_GT(design.scores[s].determined, design.baseline[s].determined);
  }
  FloatingSimulationOptions options;
  options.contacts = request.contacts;
  options.motion_from = motionOf(model, request, design);
  options.samples = options.motion_from->numSamples();
  options.friction_cone = request.friction_cone;
  options.sole = request.sole;
  std::vector<int> outside, unsupported;
  simulateFloatingDataset(model, options, nullptr, &outside, &unsupported);
  EXPECT_TRUE(outside.empty()) << outside.size() << " samples outside the cones or the soles";
  EXPECT_TRUE(unsupported.empty());
  request.sole = {{0.0, 0.0}, {0.1, 0.0}, {0.2, 0.0}};  // on a line
  EXPECT_THROW(designStandingSway(model, request), InputError);
}

/// The joints no foot depends on follow a joint design of their own (a humanoid's arms while it
/// sways): exactly the series, and the legs as without it (no foot depends on an arm).
TEST(StandingDesign, TheFreeJointsFollowTheirOwnSeriesAndTheLegsDoNotSeeThem) {
  const FloatingModel model = test::loadExample(test::kRomeoExample);
  StandingMotionRequest r;
  r.contacts = contactsOf(model, {"l_sole:frame", "r_sole:frame"});
  r.stance = Eigen::VectorXd::Zero(31);
  r.stance.head<12>() << 0, 0, -0.4, 0.8, -0.4, 0, 0, 0, -0.4, 0.8, -0.4, 0;
  r.samples = 200;
  r.check_limits = false;  // the series below is the test's, not a robot's (elbows at 0 rad)
  const auto still = standingMotion(model, r);
  FourierSeries arms;
  arms.period = 2.0;
  arms.offset = r.stance;
  arms.a = Eigen::MatrixXd::Zero(31, 2);
  arms.b = Eigen::MatrixXd::Zero(31, 2);
  arms.a.block(12, 0, 19, 1).setConstant(0.2);  // every joint after the legs
  arms.b.block(12, 1, 19, 1).setConstant(-0.1);
  arms.a(0, 0) = 5.0;  // a leg's row: unread (the feet set the legs)
  r.joint_design = arms;
  const auto moving = standingMotion(model, r);
  const std::vector<char> held = heldJoints(model, r.contacts);
  ASSERT_EQ(std::count(held.begin(), held.end(), 1), 12);  // the legs' twelve
  Eigen::VectorXd q, dq, ddq;
  for (int k = 0; k < moving->numSamples(); ++k) {
    evaluateReference(arms, moving->time[k], q, dq, ddq);
    for (int j = 0; j < 31; ++j) {
      if (held[static_cast<std::size_t>(j)]) {
        EXPECT_EQ(moving->q(j, k), still->q(j, k)) << j;
        EXPECT_EQ(moving->dq(j, k), still->dq(j, k)) << j;
        continue;
      }
      EXPECT_EQ(moving->q(j, k), q[j]) << j;
      EXPECT_EQ(moving->dq(j, k), dq[j]) << j;
      EXPECT_EQ(moving->ddq(j, k), ddq[j]) << j;
    }
  }
  r.joint_design->offset.resize(30);
  EXPECT_THROW(standingMotion(model, r), InputError);
}

TEST(StandingDesign, ADesignedPoseIsTheDerivativeOfItsOrientation) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  StandingMotionRequest r;
  r.contacts = anymalDesign(model).contacts;
  r.stance = anymalDesign(model).stance;
  FourierSeries base;
  base.period = 2.0;
  base.offset = Eigen::VectorXd::Zero(6);
  base.a.resize(6, 2);
  base.b.resize(6, 2);
  base.a << 0.02, -0.01, 0.01, 0.02, -0.01, 0.0, 0.1, 0.05, -0.1, 0.08, 0.05, -0.1;
  base.b << 0.01, 0.0, 0.0, 0.01, 0.02, 0.0, 0.05, -0.1, 0.1, 0.05, -0.08, 0.06;
  r.base_design = base;
  r.rate = 1000.0;
  r.samples = 500;
  const auto m = standingMotion(model, r);
  const double dt = 1.0 / r.rate;
  const auto rotation = [&](int k) {
    const Eigen::Vector4d o = m->orientation.col(k);
    return Eigen::Quaterniond(o[0], o[1], o[2], o[3]).toRotationMatrix();
  };
  double largest_rate = 0.0;
  for (int k = 1; k + 1 < m->numSamples(); ++k) {
    // The body rate against R^T R' by central differences, the acceleration against the twist's
    // central differences (dynid's dv = R^T p'' - omega x v is the derivative of v = R^T p'):
    // both to the differences' own error, the third derivative times dt^2 / 6 (about 1e-7).
    const Eigen::Matrix3d W =
        rotation(k).transpose() * (rotation(k + 1) - rotation(k - 1)) / (2 * dt);
    const Eigen::Vector3d omega(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((omega - m->twist.col(k).head<3>()).norm(), 1e-6) << "sample " << k;
    const Vector6<double> derivative = (m->twist.col(k + 1) - m->twist.col(k - 1)) / (2 * dt);
    EXPECT_LT((derivative - m->acceleration.col(k)).norm(), 1e-5) << "sample " << k;
    largest_rate = std::max(largest_rate, omega.norm());
  }
  EXPECT_GT(largest_rate, 0.05);  // the test turns the base (about every axis)
}

TEST(StandingDesign, TheSameSeedGivesTheSameDesign) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  StandingDesignRequest request = anymalDesign(model);
  request.starts = 1;
  request.evaluations = 30;
  const StandingDesign first = designStandingSway(model, request);
  const StandingDesign again = designStandingSway(model, request);
  EXPECT_EQ(first.base.a, again.base.a);
  EXPECT_EQ(first.base.b, again.base.b);
  request.seed = 2;
  EXPECT_NE(designStandingSway(model, request).base.a, first.base.a);
}

TEST(StandingDesign, RefusesWhatItCannotDesign) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  StandingDesignRequest request = anymalDesign(model);
  request.stance.resize(11);
  try {
    designStandingSway(model, request);
    FAIL() << "a stance of 11 joints was designed for";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "`stance` has 11 joints")) << e.what();
  }
  request = anymalDesign(model);
  request.max_sway = 0.0;
  EXPECT_THROW(designStandingSway(model, request), InputError);
  // A margin no joint of this stance keeps: the bound is named.
  request = anymalDesign(model);
  request.joint_margin = 1.0;
  request.evaluations = 20;
  try {
    designStandingSway(model, request);
    FAIL() << "a 1 rad margin was kept";
  } catch (const Error& e) {
    EXPECT_TRUE(test::contains(e.what(), "the nearest broke `joint_margin`")) << e.what();
  }
  // Legs straight: the base cannot rise.
  request = anymalDesign(model);
  request.stance.setZero();
  try {
    designStandingSway(model, request);
    FAIL() << "a straight-legged stance was designed for";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "`stance`: the legs cannot follow random sways of it"))
        << e.what();
  }
}

}  // namespace
}  // namespace dynid
