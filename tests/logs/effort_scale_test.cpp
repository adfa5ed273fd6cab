// The one conversion of motor currents into joint torques (analysis/logs/effort_scale.hpp).
#include "analysis/logs/effort_scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.hpp"

namespace dynid {
namespace {

std::string refusal(const Eigen::VectorXd& k, const Eigen::VectorXd& g, int n) {
  try {
    effortScale(k, g, n, "the robot");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EffortScale, TorqueConstantTimesGearRatioPerJoint) {
  const Eigen::Vector3d k(0.2, 0.25, 0.125), g(100.0, 160.0, 50.0);
  const Eigen::VectorXd scale = effortScale(k, g, 3, "the robot");
  ASSERT_EQ(scale.size(), 3);
  for (int j = 0; j < 3; ++j) EXPECT_EQ(scale[j], k[j] * g[j]);  // one product, exact
  // No gear ratios: the constants themselves (a ratio of 1).
  EXPECT_EQ(effortScale(k, Eigen::VectorXd(), 3, "the robot"), Eigen::VectorXd(k));
  // Neither: the efforts are torques.
  EXPECT_EQ(effortScale(Eigen::VectorXd(), Eigen::VectorXd(), 3, "the robot").size(), 0);
}

TEST(EffortScale, RefusalsNameTheField) {
  const Eigen::Vector3d k(0.2, 0.25, 0.125);
  EXPECT_NE(refusal(Eigen::VectorXd(), k, 3).find("`gear_ratios` applies to motor currents"),
            std::string::npos);
  EXPECT_NE(refusal(k, Eigen::VectorXd(), 4)
                .find("`torque_constants` has 3 values; the robot "
                      "has 4 joints"),
            std::string::npos);
  EXPECT_NE(refusal(k, Eigen::Vector2d(1.0, 2.0), 3).find("`gear_ratios` has 2 values"),
            std::string::npos);
  Eigen::Vector3d bad = k;
  bad[1] = 0.0;
  EXPECT_NE(refusal(bad, Eigen::VectorXd(), 3).find("`torque_constants`: the value of joint 2"),
            std::string::npos);
  bad[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(k, bad, 3).find("`gear_ratios`: the value of joint 2"), std::string::npos);
}

}  // namespace
}  // namespace dynid
