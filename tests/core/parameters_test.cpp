#include "core/parameters.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Parameters, NamesFollowTheConvention) {
  const std::vector<std::string> rigid = standardParameterNames({2, DriveTerms::none()});
  ASSERT_EQ(rigid.size(), 20u);
  EXPECT_EQ(rigid[0], "m1");
  EXPECT_EQ(rigid[1], "mx1");
  EXPECT_EQ(rigid[9], "Izz1");
  EXPECT_EQ(rigid[14], "Ixx2");
  const ParameterLayout drives{6, DriveTerms::of({DriveTerm::kRotorInertia, DriveTerm::kViscous,
                                                  DriveTerm::kCoulomb, DriveTerm::kOffset})};
  const std::vector<std::string> names = standardParameterNames(drives);
  ASSERT_EQ(static_cast<int>(names.size()), drives.size());
  EXPECT_EQ(drives.size(), 84);
  EXPECT_EQ(names[drives.driveIndex(2, 0)], "Ia3");
  EXPECT_EQ(names[drives.driveIndex(2, 1)], "Fv3");
  EXPECT_EQ(names[drives.driveIndex(5, 3)], "Fo6");
  // A subset keeps the column order and the names: fv,fc,fo gives Fv, Fc, Fo after each link.
  const ParameterLayout sensor{
      7, DriveTerms::of({DriveTerm::kOffset, DriveTerm::kViscous, DriveTerm::kCoulomb})};
  const std::vector<std::string> sensor_names = standardParameterNames(sensor);
  ASSERT_EQ(sensor.size(), 91);
  EXPECT_EQ(sensor_names[10], "Fv1");
  EXPECT_EQ(sensor_names[12], "Fo1");
  EXPECT_EQ(sensor_names[sensor.driveIndex(6, DriveTerm::kCoulomb)], "Fc7");
  EXPECT_EQ(sensor_names[13], "m2");
  EXPECT_EQ(names[drives.linkIndex(3, 0)], "m4");
  EXPECT_EQ(paperParameterNames(2)[8], "cx2");
}

TEST(Parameters, PaperAndStandardFormsConvertExactly) {
  Eigen::Matrix<double, 7, 1> paper;
  paper << 4.8, -0.0203, -0.0141, 0.070, 0.066, 0.086, 0.0125;
  const Eigen::Matrix<double, 10, 1> standard = paperToStandard(paper);
  // h = m c; Ixx about the origin = Ixx_c + m (cy^2 + cz^2); Ixy = -m cx cy.
  EXPECT_DOUBLE_EQ(standard(1), 4.8 * -0.0203);
  EXPECT_NEAR(standard(4), 0.066 + 4.8 * (0.0141 * 0.0141 + 0.07 * 0.07), 1e-15);
  EXPECT_NEAR(standard(5), -4.8 * -0.0203 * -0.0141, 1e-17);
  double dropped = -1.0;
  const Eigen::Matrix<double, 7, 1> back = standardToPaper(standard, &dropped);
  // Round-off of the parallel-axis shift on values of order 0.1.
  EXPECT_LT((back - paper).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT(dropped, 1e-16);
}

TEST(Parameters, ReportsDroppedProductsOfInertia) {
  Eigen::Matrix<double, 10, 1> standard;
  standard << 1.0, 0, 0, 0, 0.2, 0.05, 0, 0.3, 0, 0.4;
  double dropped = 0.0;
  standardToPaper(standard, &dropped);
  EXPECT_DOUBLE_EQ(dropped, 0.05);
}

TEST(Parameters, ConsistentLinkPasses) {
  Eigen::Matrix<double, 7, 1> paper;
  paper << 2.0, 0.1, 0.2, -0.1, 0.3, 0.4, 0.5;
  EXPECT_TRUE(checkPhysicalConsistency(fromStandardVector(paperToStandard(paper)), 0, "a").empty());
}

TEST(Parameters, EachViolationIsNamed) {
  Eigen::Matrix<double, 7, 1> paper;
  paper << -1.0, 0, 0, 0, 0.3, 0.4, 0.5;
  auto v = checkPhysicalConsistency(fromStandardVector(paperToStandard(paper)), 2, "forearm");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].condition, "mass >= 0");
  EXPECT_EQ(v[0].link_name, "forearm");
  EXPECT_EQ(v[0].link, 2);

  paper << 1.0, 0, 0, 0, 0.1, 0.1, 0.5;  // 0.1 + 0.1 < 0.5
  v = checkPhysicalConsistency(fromStandardVector(paperToStandard(paper)), 0, "l");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].condition.find("triangle inequality"), std::string::npos);
  EXPECT_NE(v[0].detail.find("0.1 + 0.1 < 0.5"), std::string::npos);

  paper << 1.0, 0, 0, 0, -0.1, 0.3, 0.3;
  v = checkPhysicalConsistency(fromStandardVector(paperToStandard(paper)), 0, "l");
  ASSERT_FALSE(v.empty());
  EXPECT_NE(v[0].condition.find("positive semi-definite"), std::string::npos);

  RigidInertia<double> massless;
  massless.first_moment = Eigen::Vector3d(0.1, 0, 0);
  massless.inertia = Eigen::Matrix3d::Identity() * 0.1;
  v = checkPhysicalConsistency(massless, 0, "l");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].condition, "a massless link has no first moment");
}

TEST(Parameters, DriveTermsParseAndPrint) {
  const DriveTerms terms = parseDriveTerms("fo,fv,fc");
  EXPECT_EQ(terms, DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb, DriveTerm::kOffset}));
  EXPECT_EQ(driveTermsText(terms), "fv,fc,fo");  // column order, whatever the input order
  EXPECT_EQ(terms.count(), 3);
  EXPECT_EQ(terms.column(static_cast<int>(DriveTerm::kOffset)), 2);
  EXPECT_EQ(terms.column(static_cast<int>(DriveTerm::kRotorInertia)), -1);
  EXPECT_EQ(terms.termAt(0), static_cast<int>(DriveTerm::kViscous));
  EXPECT_FALSE(parseDriveTerms("none").any());
  EXPECT_EQ(driveTermsText(DriveTerms::none()), "none");
  EXPECT_EQ(driveTermsText(parseDriveTerms("fa,ia")), "ia,fa");
  for (const char* bad : {"", "fv,", "fv,fx", "FV", "fv,fv", "fv fc"})
    EXPECT_THROW(parseDriveTerms(bad), InputError) << bad;
  try {
    parseDriveTerms("fv,fx");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'fx'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
