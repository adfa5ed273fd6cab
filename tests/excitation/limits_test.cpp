#include "analysis/excitation/limits.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

TEST(ExciteLimits, LimitsComeFromTheModelWithNotedDefaults) {
  const Model puma = makePuma560(false);
  const ExcitationLimits l = excitationLimits(puma, {});
  EXPECT_EQ(l.q_min[0], puma.limits[0].lower);
  EXPECT_EQ(l.q_max[5], puma.limits[5].upper);
  EXPECT_EQ(l.dq_max[2], kDefaultVelocityLimit);  // the PUMA model has no speed limits
  EXPECT_EQ(l.ddq_max[2], kDefaultAccelerationLimit);
  EXPECT_TRUE(std::isinf(l.tau_max[0]));
  ASSERT_EQ(l.notes.size(), 3u);  // velocity, acceleration, torque
  EXPECT_NE(l.notes[0].find("velocity"), std::string::npos);
  EXPECT_NE(l.notes[0].find("joint1"), std::string::npos);

  LimitOverrides o;
  o.dq_max = Eigen::VectorXd::Constant(6, 1.0);
  EXPECT_EQ(excitationLimits(puma, o).dq_max[3], 1.0);
  o.dq_max->coeffRef(3) = 0.0;
  EXPECT_THROW(excitationLimits(puma, o), InputError);
  o = {};
  o.q_min = Eigen::VectorXd::Constant(6, 1.0);
  o.q_max = Eigen::VectorXd::Constant(6, 1.0);
  EXPECT_THROW(excitationLimits(puma, o), InputError);  // an empty range
  o = {};
  o.torque_margin = 1.5;
  EXPECT_THROW(excitationLimits(puma, o), InputError);
  o = {};
  o.ddq_max = Eigen::VectorXd::Constant(5, 1.0);
  EXPECT_THROW(excitationLimits(puma, o), InputError);  // 5 entries for 6 joints
}

TEST(ExciteLimits, CheckLimitsNamesEveryKindOfViolation) {
  const Model puma = makePuma560(false);
  LimitOverrides o;
  o.tau_max = Eigen::VectorXd::Constant(6, 100.0);
  o.floor = -2.0;  // below the whole arm
  o.base_radius = 0.05;
  const ExcitationLimits limits = excitationLimits(puma, o);
  Trajectory t;
  t.resize(6, 2);
  t.time << 0.0, 0.001;
  t.q.col(1) = Eigen::VectorXd::Constant(6, 0.1);
  EXPECT_TRUE(checkLimits(puma, t, limits).violations.empty());
  auto expectViolation = [&](Trajectory bad, const std::string& what) {
    const LimitCheck c = checkLimits(puma, bad, limits);
    ASSERT_EQ(c.violations.size(), 1u) << what << ": " << c.violations.back();
    EXPECT_NE(c.violations[0].find(what), std::string::npos) << c.violations[0];
  };
  Trajectory bad = t;
  bad.q(1, 1) = limits.q_max[1] + 1e-9;
  expectViolation(bad, "joint2': position");
  bad = t;
  bad.q(1, 0) = limits.q_min[1] - 1e-9;
  expectViolation(bad, "joint2': position");
  bad = t;
  bad.dq(3, 1) = -limits.dq_max[3] * 1.001;
  expectViolation(bad, "joint4': speed");
  bad = t;
  bad.ddq(4, 0) = limits.ddq_max[4] * 1.001;
  expectViolation(bad, "joint5': acceleration");
  bad = t;
  bad.tau(0, 1) = 91.0;  // above the 0.9 margin of 100 N m
  expectViolation(bad, "joint1': torque");
  ExcitationLimits high = limits;
  high.floor = 2.0;  // above the whole arm
  const LimitCheck c = checkLimits(puma, t, high);
  ASSERT_FALSE(c.violations.empty());
  EXPECT_NE(c.violations.back().find("below the floor"), std::string::npos);
}

}  // namespace
}  // namespace dynid
