// A known body attached to a link (analysis/payload/attach.hpp): the loaded arm's torques are the
// arm's plus the body's, bodies no rigid body can be are refused, links are found by name.
#include "analysis/payload/attach.hpp"

#include <gtest/gtest.h>

#include "analysis/payload/body.hpp"
#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/payload_logs.hpp"

namespace dynid {
namespace {

TEST(Attach, TheLoadedArmIsTheArmPlusTheBody) {
  const Model arm = makePuma560(true);
  const Vector10d body = test::toolBody();
  const Model loaded = attachBody(arm, 5, test::pumaFlange(), body);
  // The same as the tests' own loaded arm, and the arm's drive terms kept.
  const Model reference = test::withPayload(arm, 5, test::pumaFlange(), body);
  EXPECT_LT((loaded.standardParameters() - reference.standardParameters()).norm(),
            1e-14 * reference.standardParameters().norm());
  EXPECT_EQ(loaded.driveTerms().has(DriveTerm::kCoulomb),
            arm.driveTerms().has(DriveTerm::kCoulomb));
  // Its torques minus the arm's are the body's alone: zero at joint torques the body cannot feel
  // is not claimed; the mass it adds is exact.
  EXPECT_NEAR(loaded.inertias()[5].mass - arm.inertias()[5].mass, body[0], 1e-14);
  Data a(arm), l(loaded);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(6, 0.3), zero = Eigen::VectorXd::Zero(6);
  const Eigen::VectorXd difference = rnea(loaded, l, q, zero, zero) - rnea(arm, a, q, zero, zero);
  EXPECT_GT(difference.norm(), 1e-3);  // the tool's weight (1.2 kg) shows at the joints
  EXPECT_THROW(attachBody(arm, 6, Pose<double>::Identity(), body), InputError);
}

TEST(Attach, BodyFromItsCentreAndItsRefusals) {
  // 2 kg at (0.1, 0, 0) with moments 0.01, 0.02, 0.03 about its centre: the frame-origin inertia
  // adds m c^2 to Iyy and Izz (0.02 each).
  Eigen::Matrix3d inertia = Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal();
  const Vector10d b = bodyFromCentre(2.0, Eigen::Vector3d(0.1, 0.0, 0.0), inertia);
  Vector10d expected;
  expected << 2.0, 0.2, 0.0, 0.0, 0.01, 0.0, 0.0, 0.04, 0.0, 0.05;
  EXPECT_LT((b - expected).norm(), 1e-15);
  // A point mass is a body; a principal moment above the sum of the other two is not.
  EXPECT_NO_THROW(bodyFromCentre(0.5, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero()));
  inertia = Eigen::Vector3d(0.001, 0.001, 0.01).asDiagonal();
  EXPECT_THROW(bodyFromCentre(1.0, Eigen::Vector3d::Zero(), inertia), InputError);
  EXPECT_THROW(bodyFromCentre(0.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero()), InputError);
  inertia.setZero();
  inertia(0, 1) = 0.01;  // not symmetric
  EXPECT_THROW(bodyFromCentre(1.0, Eigen::Vector3d::Zero(), inertia), InputError);
}

TEST(Attach, LinksByName) {
  const Model arm = makePuma560(false);
  EXPECT_EQ(linkIndex(arm, ""), 5);
  EXPECT_EQ(linkIndex(arm, arm.link_names[2]), 2);
  try {
    linkIndex(arm, "gripper");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("`link` 'gripper'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
