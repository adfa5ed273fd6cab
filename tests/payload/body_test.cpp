// A payload's body in the forms vendors ask for (analysis/payload/body.hpp): the principal body and
// KUKA's and ABB's angle conventions, each round-tripped and checked on a hand-computed case.
#include "analysis/payload/body.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/spatial.hpp"
#include "tests/common/payload_logs.hpp"

namespace dynid {
namespace {

TEST(PayloadBody, PrincipalBodyAndTheVendorsAnglesRoundTrip) {
  const Vector10d body = test::toolBody();
  const PrincipalBody p = principalBody(body);
  EXPECT_LT((standardFromPrincipal(p) - body).norm(), 1e-14 * body.norm());
  EXPECT_NEAR(p.axes.determinant(), 1.0, 1e-12);
  EXPECT_LT((rotationFromKukaAbc(kukaAbc(p.axes)) - p.axes).norm(), 1e-12);
  EXPECT_LT((rotationFromAbbQuaternion(abbQuaternion(p.axes)) - p.axes).norm(), 1e-12);
  // Hand-computed: a 90 degree turn about z is A = 90, B = C = 0, and q = (cos 45, 0, 0, sin 45).
  const Eigen::Matrix3d rz = rotationFromRpy(0.0, 0.0, M_PI / 2);
  EXPECT_LT((kukaAbc(rz) - Eigen::Vector3d(M_PI / 2, 0, 0)).norm(), 1e-12);
  EXPECT_LT((abbQuaternion(rz) - Eigen::Vector4d(std::sqrt(0.5), 0, 0, std::sqrt(0.5))).norm(),
            1e-12);
  // Axis-aligned inertia keeps the identity (the nearest of the 24 orderings).
  Vector10d aligned = Vector10d::Zero();
  aligned << 2.0, 0, 0, 0, 0.3, 0, 0, 0.1, 0, 0.2;
  const PrincipalBody a = principalBody(aligned);
  EXPECT_LT((a.axes - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((a.moments - Eigen::Vector3d(0.3, 0.1, 0.2)).norm(), 1e-12);
}

}  // namespace
}  // namespace dynid
