#include "data/puma560.hpp"

#include <numbers>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {
namespace {

TEST(Puma560, ParametersAreThePublishedOnes) {
  const Model model = makePuma560();
  ASSERT_EQ(model.numJoints(), 6);
  EXPECT_FALSE(model.driveTerms().any());
  EXPECT_EQ(model.gravity(), Eigen::Vector3d(0, 0, -9.81));
  // Link 2 in paper form, back from the standard parameters (shared/reference/puma560.md).
  const auto p2 = standardToPaper(toStandardVector(model.inertias()[1]));
  Eigen::Matrix<double, 7, 1> expected;
  expected << 17.4, -0.3638, 0.006, 0.2275, 0.13, 0.524, 0.539;
  EXPECT_LT((p2 - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(model.inertias()[0].mass, 0.0);
  EXPECT_DOUBLE_EQ(model.inertias()[0].inertia(1, 1), 0.35);
  EXPECT_DOUBLE_EQ(model.limits[3].upper, 266.0 * std::numbers::pi / 180.0);
}

TEST(Puma560, DrivesOnTheJointSide) {
  const Model model = makePuma560(true);
  EXPECT_EQ(model.driveTerms(), kPuma560DriveTerms);
  EXPECT_EQ(driveTermsText(model.driveTerms()), "ia,fv,fc,fa");
  EXPECT_EQ(model.parameterLayout().size(), 84);
  const DriveParameters<double>& d1 = model.drives()[0];
  EXPECT_DOUBLE_EQ(d1[DriveTerm::kRotorInertia], 200e-6 * 62.6111 * 62.6111);
  EXPECT_DOUBLE_EQ(d1[DriveTerm::kViscous], 62.6111 * 62.6111 * 1.48e-3);
  // |G| Tc+ for dq > 0 and |G| Tc- for dq < 0, as Fc sign(dq) + Fa |sign(dq)|.
  EXPECT_NEAR(d1[DriveTerm::kCoulomb] + d1[DriveTerm::kCoulombAsymmetry], 62.6111 * 0.395, 1e-12);
  EXPECT_NEAR(-d1[DriveTerm::kCoulomb] + d1[DriveTerm::kCoulombAsymmetry], 62.6111 * -0.435, 1e-12);
  EXPECT_EQ(d1[DriveTerm::kOffset], 0.0);
}

TEST(Puma560, ConsistencyCheckReportsThePublishedValuesUnchanged) {
  // The consensus set's link 1 (inertia only about y) and link 3 fail the triangle inequality.
  const Model model = makePuma560();
  std::vector<std::string> failing;
  for (int i = 0; i < 6; ++i)
    for (const auto& v : checkPhysicalConsistency(model.inertias()[i], i, model.link_names[i]))
      failing.push_back(v.link_name + ": " + v.condition);
  ASSERT_EQ(failing.size(), 2u);
  EXPECT_EQ(failing[0].substr(0, 7), "link1: ");
  EXPECT_EQ(failing[1].substr(0, 7), "link3: ");
}

TEST(Puma560, NamedPoses) {
  EXPECT_DOUBLE_EQ(puma560Pose("qr")[1], std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(puma560Pose("qn")[2], std::numbers::pi);
  EXPECT_THROW(puma560Pose("qx"), InputError);
}

}  // namespace
}  // namespace dynid
