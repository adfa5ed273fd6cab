#include "core/spatial.hpp"

#include <random>

#include <gtest/gtest.h>

#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// Round-off of a few 3x3 products on O(1) numbers.
constexpr double kTol = 1e-12;

Pose<double> randomPose(std::mt19937_64& rng) {
  const Eigen::VectorXd x = test::randomVector(rng, 6, 2.0);
  Pose<double> pose;
  pose.rotation = rotationFromRpy(x[0], x[1], x[2]);
  pose.translation = x.tail<3>();
  return pose;
}

TEST(Spatial, PoseInverseAndComposition) {
  std::mt19937_64 rng(1);
  const Pose<double> a = randomPose(rng), b = randomPose(rng);
  const Pose<double> identity = a * a.inverse();
  EXPECT_LT((identity.rotation - Eigen::Matrix3d::Identity()).norm(), kTol);
  EXPECT_LT(identity.translation.norm(), kTol);
  const Eigen::Vector3d x(0.3, -0.1, 0.7);
  EXPECT_LT(((a * b).rotation * x + (a * b).translation -
             (a.rotation * (b.rotation * x + b.translation) + a.translation))
                .norm(),
            kTol);
}

TEST(Spatial, MotionTransformsInvertAndPreservePower) {
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose<double> X = randomPose(rng);
    const Vector6<double> m = test::randomVector(rng, 6, 1.0), f = test::randomVector(rng, 6, 1.0);
    EXPECT_LT((X.actInvMotion(X.actMotion(m)) - m).norm(), kTol);
    // Power is frame independent: (pXi* f) . m_parent = f . (iXp m_parent).
    EXPECT_NEAR(X.actForce(f).dot(m), f.dot(X.actInvMotion(m)), kTol);
  }
}

TEST(Spatial, CrossProductsAreDual) {
  std::mt19937_64 rng(3);
  const Vector6<double> v = test::randomVector(rng, 6, 1.0), m = test::randomVector(rng, 6, 1.0),
                        f = test::randomVector(rng, 6, 1.0);
  // (v x* f) . m = -f . (v x m)
  EXPECT_NEAR(crossForce(v, f).dot(m), -f.dot(crossMotion(v, m)), kTol);
  EXPECT_LT(crossMotion(v, v).norm(), kTol);
  EXPECT_LT(
      (cross(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()) - Eigen::Vector3d::UnitZ()).norm(),
      0.0 + 1e-300);
}

TEST(Spatial, InertiaTransformMatchesTransformedMomentum) {
  std::mt19937_64 rng(4);
  RigidInertia<double> inertia;
  inertia.mass = 2.5;
  inertia.first_moment = Eigen::Vector3d(0.2, -0.1, 0.3);
  inertia.inertia << 0.5, 0.01, -0.02, 0.01, 0.4, 0.03, -0.02, 0.03, 0.6;
  const Pose<double> X = randomPose(rng);
  const Vector6<double> m = test::randomVector(rng, 6, 1.0);
  // (pXi* I iXp) m, computed two ways.
  const Vector6<double> direct = X.actForce(inertia.apply(X.actInvMotion(m)));
  EXPECT_LT((inertia.transformedBy(X).apply(m) - direct).norm(), kTol);
  EXPECT_LT((inertia.matrix() * m - inertia.apply(m)).norm(), kTol);
}

TEST(Spatial, RollPitchYawRoundTrip) {
  const Eigen::Matrix3d r = rotationFromRpy(0.3, -1.1, 2.4);
  const Eigen::Vector3d rpy = rpyFromRotation(r);
  EXPECT_LT((rotationFromRpy(rpy[0], rpy[1], rpy[2]) - r).norm(), kTol);
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, -2).normalized();
  const Eigen::Matrix3d ra = axisAngle<double>(axis, 0.7);
  EXPECT_LT((ra * axis - axis).norm(), kTol);
  EXPECT_LT((ra * ra.transpose() - Eigen::Matrix3d::Identity()).norm(), kTol);
}

}  // namespace
}  // namespace dynid
