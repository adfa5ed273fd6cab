#include "identifiability/base_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dynid {
namespace {

TEST(BaseEstimate, RelativeErrorsFromTheJointRms) {
  BaseEstimate e;
  e.residual_rms = Eigen::Vector3d(0.3, 0.4, 0.1);
  e.measured_rms = Eigen::Vector3d(3.0, 4.0, 0.0);
  setRelativeErrors(e);
  EXPECT_DOUBLE_EQ(e.joint_relative_error[0], 0.1);
  EXPECT_DOUBLE_EQ(e.joint_relative_error[1], 0.1);
  EXPECT_EQ(e.joint_relative_error[2], std::numeric_limits<double>::infinity());  // tau = 0
  // Over all rows: |r| / |tau| from equal sample counts, sqrt(0.26) / 5.
  EXPECT_DOUBLE_EQ(e.relative_error, std::sqrt(0.26) / 5.0);
  e.measured_rms.setZero();
  setRelativeErrors(e);
  EXPECT_EQ(e.relative_error, std::numeric_limits<double>::infinity());
}

TEST(BaseEstimate, MethodNames) {
  EXPECT_STREQ(leastSquaresMethodName(LeastSquaresMethod::kOrdinary), "ols");
  EXPECT_STREQ(leastSquaresMethodName(LeastSquaresMethod::kWeighted), "wls");
}

}  // namespace
}  // namespace dynid
