// Contact Jacobians against central differences of the contact frame's pose.
#include <gtest/gtest.h>

#include "core/floating/contact_jacobian.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

TEST(ContactJacobian, EqualsDifferencesOfTheContactsPose) {
  const FloatingModel model = test::randomFloating(3, {.num_bodies = 6});
  FloatingData data(model);
  std::mt19937_64 rng(3);
  const int n = model.numJoints();
  for (int body = -1; body < n; ++body) {
    Contact contact;
    contact.name = "c" + std::to_string(body);
    contact.body = body;
    contact.placement.rotation = rotationFromRpy(0.3, -0.2, 0.9);
    contact.placement.translation << 0.1, -0.05, 0.2;
    contact.kind = body % 2 == 0 ? Contact::Kind::kPoint : Contact::Kind::kFrame;
    const Eigen::VectorXd q = test::randomVector(rng, n, 1.5);
    const Eigen::VectorXd velocity = test::randomVector(rng, 6 + n, 1.0);
    const Eigen::MatrixXd J = contactJacobian(model, data, contact, q);
    ASSERT_EQ(J.rows(), contact.dimension());
    // The pose in the base frame after a step h of the base twist (a rotation exp(omega h) and a
    // translation v h, to first order in h) and of the joints; central differences.
    const double h = 1e-6;
    const auto poseAt = [&](double t) {
      const Pose<double> local = contactPose(model, data, contact, q + t * velocity.tail(n));
      Pose<double> moved;
      moved.rotation = axisAngle(Eigen::Vector3d(velocity.head<3>().normalized()),
                                 velocity.head<3>().norm() * t);
      moved.translation = velocity.segment<3>(3) * t;
      return moved * local;
    };
    const Pose<double> up = poseAt(h), down = poseAt(-h), here = poseAt(0.0);
    const Eigen::Vector3d linear = (up.translation - down.translation) / (2 * h);
    const Eigen::Matrix3d spin =
        (up.rotation - down.rotation) / (2 * h) * here.rotation.transpose();
    const Eigen::Vector3d angular(spin(2, 1), spin(0, 2), spin(1, 0));
    const Eigen::VectorXd expected = contact.kind == Contact::Kind::kPoint
                                         ? Eigen::VectorXd(linear)
                                         : (Eigen::VectorXd(6) << angular, linear).finished();
    // Central differences at h = 1e-6: truncation ~h^2, round-off ~1e-16 / h.
    EXPECT_LT((J * velocity - expected).norm(), 1e-8) << "body " << body;
  }
}

TEST(ContactJacobian, RefusesABodyTheModelLacks) {
  const FloatingModel model = test::randomFloating(3, {.num_bodies = 3});
  FloatingData data(model);
  Contact contact;
  contact.name = "heel";
  contact.body = 3;
  try {
    contactJacobian(model, data, contact, Eigen::VectorXd::Zero(3));
    FAIL() << "a contact on body 3 of 3 was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'heel'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
