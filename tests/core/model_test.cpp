#include "core/model.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/kinematics.hpp"
#include "core/perturb.hpp"
#include "core/rnea.hpp"
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
  for (int i = 1; i < puma.numJoints(); ++i) EXPECT_GE(puma.placement_permutation()[i], 0) << i;
  // Rx(pi/2) from its cosine (6e-17, not 0) is not a signed permutation: the general path.
  Model model = puma;
  const double c = std::cos(M_PI / 2), s = std::sin(M_PI / 2);
  Pose<double> placement = model.body_placements()[0];
  placement.rotation << 1, 0, 0, 0, c, -s, 0, s, c;
  model.setBodyPlacement(0, placement);
  EXPECT_EQ(model.placement_permutation()[1], -1);
  // Rz(90 degrees) maps x to y: rotation(0, 1) = -1, rotation(1, 0) = 1, permutation (1, 0, 2).
  placement.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  placement.translation << 0.1, 0.2, 0.3;
  model.setBodyPlacement(0, placement);
  EXPECT_EQ(model.placement_permutation()[1], 2);
  // det(Pi) Pi^T t = -(0.2, 0.1, 0.3) for the odd permutation (1, 0, 2).
  EXPECT_EQ(model.placement_shift()[1], Eigen::Vector3d(-0.2, -0.1, -0.3));
}

TEST(Model, StandardParametersRoundTrip) {
  Model model = test::randomTree(5, {.drives = true});
  const Eigen::VectorXd theta = model.standardParameters();
  EXPECT_EQ(theta.size(), model.numJoints() * (10 + kDriveTermCount));  // every drive term
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
    if (model.joint_types()[i] == JointType::kPrismatic)
      motion.translation = model.axes()[i] * q[i];
    else
      motion.rotation = axisAngle<double>(model.axes()[i], q[i]);
    const Pose<double> local = model.joint_placements()[i] * motion * model.body_placements()[i];
    expected[i] = model.parents()[i] < 0 ? local : expected[model.parents()[i]] * local;
    // Round-off of a chain of up to 7 transforms.
    EXPECT_LT((data.oMi[i].rotation - expected[i].rotation).norm(), 1e-12) << i;
    EXPECT_LT((data.oMi[i].translation - expected[i].translation).norm(), 1e-12) << i;
  }
}

// The sealed model: no public call leaves a derived cache stale.
TEST(Model, StructureAndParametersAreReadOnlyOutsideTheSetters) {
  // Every accessor hands out a const reference (writing through one does not compile).
  const auto is_const_ref = [](auto&& field) {
    return std::is_const_v<std::remove_reference_t<decltype(field)>>;
  };
  Model model = makePuma560(true);
  EXPECT_TRUE(is_const_ref(model.inertias()));
  EXPECT_TRUE(is_const_ref(model.drives()));
  EXPECT_TRUE(is_const_ref(model.parents()));
  EXPECT_TRUE(is_const_ref(model.joint_placements()));
  EXPECT_TRUE(is_const_ref(model.body_placements()));
  EXPECT_TRUE(is_const_ref(model.axes()));
  EXPECT_TRUE(is_const_ref(model.frame_inertias()));
  EXPECT_TRUE(is_const_ref(model.frame_inertia_matrices()));
  EXPECT_TRUE(is_const_ref(model.frame_placements()));
  EXPECT_TRUE(model.cachesAreCurrent());
}

TEST(Model, EverySetterKeepsTheCachesCurrent) {
  Model model = test::randomTree(7, {.drives = true});
  ASSERT_TRUE(model.cachesAreCurrent());
  RigidInertia<double> inertia = model.inertias()[2];
  inertia.mass *= 1.7;
  inertia.first_moment *= -0.5;
  model.setLinkInertia(2, inertia);
  EXPECT_TRUE(model.cachesAreCurrent());
  EXPECT_EQ(model.inertias()[2].mass, inertia.mass);
  std::vector<RigidInertia<double>> all = model.inertias();
  for (auto& link : all) link.inertia *= 1.1;
  model.setLinkInertias(all);
  EXPECT_TRUE(model.cachesAreCurrent());
  model.setStandardParameters(model.standardParameters() * 0.9);
  EXPECT_TRUE(model.cachesAreCurrent());
  Pose<double> placement = model.body_placements()[1];
  placement.translation.x() += 0.25;
  model.setBodyPlacement(1, placement);
  EXPECT_TRUE(model.cachesAreCurrent());
  placement = model.joint_placements()[3];
  placement.translation.z() -= 0.1;
  model.setJointPlacement(3, placement);
  EXPECT_TRUE(model.cachesAreCurrent());
  DriveParameters<double> drive = model.drives()[0];
  drive[DriveTerm::kViscous] = 2.5;
  model.setDrive(0, drive);
  EXPECT_EQ(model.drives()[0][DriveTerm::kViscous], 2.5);
  EXPECT_THROW(model.setLinkInertia(model.numJoints(), inertia), InputError);
  EXPECT_THROW(model.setLinkInertias({}), InputError);
}

TEST(Model, CachesAreCurrentDetectsAStaleCache) {
  // Caches not yet derived (before finalize) and caches left behind by a body added after it are
  // both seen, and the algorithms refuse such a model rather than read the stale caches.
  Model model;
  model.addBody(-1, "a", "j1", JointType::kRevolute, {}, Eigen::Vector3d::UnitZ(), Pose<double>(),
                test::randomTree(1).inertias()[0]);
  EXPECT_FALSE(model.cachesAreCurrent());
  model.finalize();
  EXPECT_TRUE(model.cachesAreCurrent());
  model.addBody(0, "b", "j2", JointType::kRevolute, {}, Eigen::Vector3d::UnitY(), Pose<double>(),
                test::randomTree(1).inertias()[1]);
  EXPECT_FALSE(model.finalized());
  EXPECT_FALSE(model.cachesAreCurrent());
  Model finished = model;
  finished.finalize();
  Data data(finished);
  EXPECT_THROW(rnea(model, data, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2),
                    Eigen::VectorXd::Zero(2)),
               InputError);
  // The perturbed model, built through the setters, agrees with its own caches (the stale cache
  // that once gave a wrong result there cannot recur).
  EXPECT_TRUE(perturbedModel(makePuma560(false), 0.3, 5).cachesAreCurrent());
}

}  // namespace
}  // namespace dynid
