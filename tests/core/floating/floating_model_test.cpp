// The floating model: its parameter vector, names and base quaternions.
#include <gtest/gtest.h>

#include "core/floating/floating_model.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

TEST(FloatingModel, ParametersAreTheBaseBodysThenTheLimbs) {
  FloatingModel model = test::randomFloating(1, {.num_bodies = 3, .drives = true});
  const Eigen::VectorXd theta = model.standardParameters();
  ASSERT_EQ(theta.size(), 10 + model.limbs().parameterLayout().size());
  EXPECT_EQ(theta.head<10>(), toStandardVector(model.baseInertia()));
  EXPECT_EQ(theta.tail(theta.size() - 10), model.limbs().standardParameters());
  const std::vector<std::string> names = floatingParameterNames(model);
  ASSERT_EQ(static_cast<int>(names.size()), theta.size());
  EXPECT_EQ(names[0], "m0");
  EXPECT_EQ(names[9], "Izz0");
  EXPECT_EQ(names[10], "m1");
  Eigen::VectorXd changed = theta;
  changed[0] += 1.0, changed[10] += 2.0;
  model.setStandardParameters(changed);
  EXPECT_EQ(model.standardParameters(), changed);
  EXPECT_THROW(model.setStandardParameters(theta.head(5)), InputError);
  changed[0] = -1.0;
  EXPECT_THROW(model.setStandardParameters(changed), InputError);
}

TEST(FloatingModel, RefusesAnUnfinalizedOrNonFiniteModel) {
  Model unfinished;
  unfinished.addBody(-1, "link", "joint", JointType::kRevolute, Pose<double>(),
                     Eigen::Vector3d::UnitZ(), Pose<double>(), RigidInertia<double>());
  EXPECT_THROW(FloatingModel(unfinished, RigidInertia<double>()), InputError);
  RigidInertia<double> nan_base;
  nan_base.inertia(1, 1) = std::nan("");
  EXPECT_THROW(FloatingModel(test::randomTree(1), nan_base), InputError);
}

TEST(BaseRotation, NormalisesRoundOffAndRefusesAnythingElse) {
  const Eigen::Vector4d half_turn_z(0.0, 0.0, 0.0, 1.0);
  EXPECT_TRUE(
      baseRotation(half_turn_z).isApprox(Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix()));
  // A single-precision log's quaternion (norm 1 + 1e-7) is normalised: a rotation again.
  const Eigen::Vector4d nearly = Eigen::Vector4d(0.5, 0.5, 0.5, 0.5) * (1.0 + 1e-7);
  const Eigen::Matrix3d r = baseRotation(nearly);
  EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-15);
  // Beyond 1e-3 it is refused, naming the field and the norm.
  try {
    baseRotation(Eigen::Vector4d(1.0, 0.1, 0.0, 0.0), "orientation");
    FAIL() << "a quaternion of norm 1.005 was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("`orientation`"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("norm is 1.00499"), std::string::npos) << e.what();
  }
  EXPECT_THROW(baseRotation(Eigen::Vector4d(std::nan(""), 0, 0, 1)), InputError);
  EXPECT_THROW(baseRotation(Eigen::Vector4d::Zero().eval()), InputError);
}

}  // namespace
}  // namespace dynid
