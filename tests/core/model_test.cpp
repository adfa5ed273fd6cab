#include "core/model.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/kinematics.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Model, AddBodyRejectsUnknownParent) {
  Model model;
  EXPECT_THROW(
      model.addBody(0, "a", "j", JointType::kRevolute, {}, Eigen::Vector3d::UnitZ(), {}, {}),
      InputError);
}

TEST(Model, FinalizeNamesTheBodyAtFault) {
  Model model;
  model.addBody(-1, "upper_arm", "shoulder", JointType::kRevolute, {}, Eigen::Vector3d(1, 1, 0), {},
                {});
  try {
    model.finalize();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'upper_arm' (joint 'shoulder')"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("unit vector"), std::string::npos);
  }
  Model nan_model;
  RigidInertia<double> bad;
  bad.mass = std::nan("");
  nan_model.addBody(-1, "l", "j", JointType::kRevolute, {}, Eigen::Vector3d::UnitZ(), {}, bad);
  EXPECT_THROW(nan_model.finalize(), InputError);
}

TEST(Model, FinalizeFindsSignedPermutationPlacements) {
  // The PUMA's DH twists are 0 and +-90 degrees, written with exact 0 and +-1 entries.
  const Model puma = makePuma560(false);
  for (int i = 1; i < puma.numJoints(); ++i) EXPECT_GE(puma.placement_permutation[i], 0) << i;
  // Rx(pi/2) from its cosine (6e-17, not 0) is not a signed permutation: the general path.
  Model model = puma;
  const double c = std::cos(M_PI / 2), s = std::sin(M_PI / 2);
  model.body_placements[0].rotation << 1, 0, 0, 0, c, -s, 0, s, c;
  model.finalize();
  EXPECT_EQ(model.placement_permutation[1], -1);
  // Rz(90 degrees) maps x to y: rotation(0, 1) = -1, rotation(1, 0) = 1, permutation (1, 0, 2).
  model.body_placements[0].rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  model.body_placements[0].translation << 0.1, 0.2, 0.3;
  model.finalize();
  EXPECT_EQ(model.placement_permutation[1], 2);
  // det(Pi) Pi^T t = -(0.2, 0.1, 0.3) for the odd permutation (1, 0, 2).
  EXPECT_EQ(model.placement_shift[1], Eigen::Vector3d(-0.2, -0.1, -0.3));
}

TEST(Model, StandardParametersRoundTrip) {
  Model model = test::randomTree(5, {.drives = true});
  const Eigen::VectorXd theta = model.standardParameters();
  EXPECT_EQ(theta.size(), model.numJoints() * 14);
  Eigen::VectorXd changed = theta * 1.5;
  model.setStandardParameters(changed);
  EXPECT_EQ(model.standardParameters(), changed);
  EXPECT_THROW(model.setStandardParameters(Eigen::VectorXd::Zero(3)), InputError);
}

TEST(Model, JointTransformsComposeToTheLinkFrames) {
  // oMi from forwardKinematics equals the naive product of
  // joint_placement * J(q) * body_placement along the chain of link frames.
  const Model model = test::randomTree(11);
  Data data(model);
  std::mt19937_64 rng(3);
  const Eigen::VectorXd q = test::randomVector(rng, model.numJoints(), 1.0);
  forwardKinematics(model, data, q);
  std::vector<Pose<double>> expected(model.numJoints());
  for (int i = 0; i < model.numJoints(); ++i) {
    Pose<double> motion;
    if (model.joint_types[i] == JointType::kPrismatic)
      motion.translation = model.axes[i] * q[i];
    else
      motion.rotation = axisAngle<double>(model.axes[i], q[i]);
    const Pose<double> local = model.joint_placements[i] * motion * model.body_placements[i];
    expected[i] = model.parents[i] < 0 ? local : expected[model.parents[i]] * local;
    // Round-off of a chain of up to 7 transforms.
    EXPECT_LT((data.oMi[i].rotation - expected[i].rotation).norm(), 1e-12) << i;
    EXPECT_LT((data.oMi[i].translation - expected[i].translation).norm(), 1e-12) << i;
  }
}

}  // namespace
}  // namespace dynid
