#include "data/dh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "data/urdf.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// Joint and link names of the test chains (as constants: GCC 12 warns falsely, -Wrestrict, on
// strings built in these loops).
const std::string kNames[7][2] = {{"j1", "l1"}, {"j2", "l2"}, {"j3", "l3"}, {"j4", "l4"},
                                  {"j5", "l5"}, {"j6", "l6"}, {"j7", "l7"}};

constexpr double kPi = std::numbers::pi;

/// The planar 2R of tests/common as a DH chain: link i has mass m_i at lc_i from joint i along
/// the link and inertia Izz_i about its centre of mass.
DhModel planarDh(DhConvention convention) {
  const test::Planar2R arm;
  const double l2 = 0.6;  // the second link's length: only the standard frames see it
  DhModel dh;
  dh.name = "planar";
  dh.convention = convention;
  dh.gravity = Eigen::Vector3d(0.0, -arm.g, 0.0);
  const double m[2] = {arm.m1, arm.m2}, lc[2] = {arm.lc1, arm.lc2}, izz[2] = {arm.I1, arm.I2};
  const double l[2] = {arm.l1, l2};
  for (int i = 0; i < 2; ++i) {
    DhRow r;
    r.joint_name = kNames[i][0];
    r.link_name = kNames[i][1];
    Eigen::Matrix3d about_com = Eigen::Matrix3d::Identity() * 0.01;
    about_com(2, 2) = izz[i];
    if (convention == DhConvention::kStandard) {
      // Frame i at the link's tip: a_i = l_i, the centre of mass at lc_i - l_i along x_i.
      r.a = l[i];
      r.inertia = inertiaFromCom(m[i], Eigen::Vector3d(lc[i] - l[i], 0, 0), about_com);
    } else {
      // Frame i at joint i: a_{i-1} = l_{i-1}, the centre of mass at lc_i along x_i.
      r.a = i == 0 ? 0.0 : l[0];
      r.inertia = inertiaFromCom(m[i], Eigen::Vector3d(lc[i], 0, 0), about_com);
    }
    dh.rows.push_back(r);
  }
  return dh;
}

TEST(Dh, BothConventionsGiveTheClosedFormPlanarDynamics) {
  const test::Planar2R arm;
  std::mt19937_64 rng(3);
  for (DhConvention convention : {DhConvention::kStandard, DhConvention::kModified}) {
    const Model model = modelFromDh(planarDh(convention));
    Data data(model);
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::Vector2d q = test::randomVector(rng, 2, 3.0),
                            dq = test::randomVector(rng, 2, 2.0),
                            ddq = test::randomVector(rng, 2, 5.0);
      const Eigen::Vector2d expected =
          arm.massMatrix(q) * ddq + arm.coriolis(q, dq) + arm.gravity(q);
      // Round-off of torques of order 10 N m.
      EXPECT_LT((rnea(model, data, q, dq, ddq) - expected).norm(), 1e-12)
          << dhConventionName(convention) << " " << trial;
    }
  }
}

TEST(Dh, TheStandardPumaTableIsTheBuiltInPuma) {
  // The built-in PUMA's DH table, through modelFromDh: the same placements to the last bit.
  const Model puma = makePuma560(false);
  DhModel dh;
  dh.name = "puma";
  const double d[6] = {0, 0, 0.15005, 0.4318, 0, 0}, a[6] = {0, 0.4318, 0.0203, 0, 0, 0};
  const double alpha[6] = {kPi / 2, 0, -kPi / 2, kPi / 2, -kPi / 2, 0};
  for (int i = 0; i < 6; ++i) {
    DhRow r;
    r.joint_name = puma.joint_names[i];
    r.link_name = puma.link_names[i];
    r.a = a[i], r.d = d[i], r.alpha = alpha[i];
    r.inertia = puma.inertias()[i];
    r.limits = puma.limits[i];
    dh.rows.push_back(r);
  }
  const Model model = modelFromDh(dh);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(model.body_placements()[i].rotation, puma.body_placements()[i].rotation) << i;
    EXPECT_EQ(model.body_placements()[i].translation, puma.body_placements()[i].translation) << i;
    // Quarter turns are exact: ABA's permuted path is taken as for the built-in model.
    EXPECT_EQ(model.placement_permutation()[i], puma.placement_permutation()[i]) << i;
  }
}

TEST(Dh, ModifiedPandaExportsToAUrdfWithTheSameDynamics) {
  const Model panda = makePanda(false);
  const Model back = parseUrdf(modelToUrdf(panda), "panda.urdf", {});
  Data a(panda), b(back);
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = test::randomVector(rng, 7, 2.5), dq = test::randomVector(rng, 7, 2.0),
                          ddq = test::randomVector(rng, 7, 5.0);
    const Eigen::VectorXd tau = rnea(panda, a, q, dq, ddq);
    // The URDF writes every number in round-trip form: round-off of torques of order 10 N m.
    EXPECT_LT((rnea(back, b, q, dq, ddq) - tau).norm(), 1e-12 * (1.0 + tau.norm())) << trial;
  }
}

TEST(Dh, AJsonDhBlockLoadsAndNamesItsErrors) {
  const std::string good = R"({"schema_version": 1, "kind": "dynid.model", "name": "two",
    "gravity": [0, 0, -9.81], "drive_terms": ["fv", "fc", "fo"],
    "dh": {"convention": "modified", "inertia_about": "com", "joints": [
      {"name": "j1", "link": "l1", "type": "revolute", "a": 0, "d": 0.3, "alpha": 0,
       "limits": {"lower": -2, "upper": 2, "velocity": 2, "acceleration": 10, "effort": 50},
       "drive": {"Fv": 0.5, "Fo": -0.25},
       "inertial": {"m": 2, "com": [0, 0.1, 0],
                    "inertia": {"Ixx": 0.1, "Ixy": 0, "Ixz": 0, "Iyy": 0.1, "Iyz": 0, "Izz": 0.1}}},
      {"name": "j2", "link": "l2", "type": "prismatic", "a": 0.1, "d": 0, "alpha": -1.5707963267948966,
       "inertial": {"m": 1, "com": [0, 0, 0.2],
                    "inertia": {"Ixx": 0.01, "Ixy": 0, "Ixz": 0, "Iyy": 0.01, "Iyz": 0, "Izz": 0.01}}}]}})";
  const Model model = modelFromJson(good, "two.json");
  ASSERT_EQ(model.numJoints(), 2);
  EXPECT_EQ(model.limits[0].acceleration, 10.0);
  EXPECT_EQ(model.joint_types()[1], JointType::kPrismatic);
  EXPECT_NEAR(model.inertias()[0].first_moment.y(), 0.2, 1e-15);  // m c
  EXPECT_EQ(driveTermsText(model.driveTerms()), "fv,fc,fo");
  EXPECT_EQ(model.drives()[0][DriveTerm::kViscous], 0.5);
  EXPECT_EQ(model.drives()[0][DriveTerm::kOffset], -0.25);
  EXPECT_EQ(model.drives()[0][DriveTerm::kCoulomb], 0.0);  // absent: 0
  // Each mistake is named by its JSON path.
  const auto fails_at = [&](const std::string& from, const std::string& to,
                            const std::string& element) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    try {
      modelFromJson(text, "bad.json");
      ADD_FAILURE() << "no error for " << to;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), "bad.json");
      EXPECT_EQ(e.element(), element) << e.what();
    }
  };
  fails_at(R"("convention": "modified")", R"("convention": "craig")", "dh.convention");
  fails_at(R"("inertia_about": "com")", R"("inertia_about": "centre")", "dh.inertia_about");
  fails_at(R"("d": 0.3)", R"("d": "0.3")", "dh.joints[0].d");
  fails_at(R"("alpha": 0,)", R"("alhpa": 0,)", "dh.joints[0].alhpa");
  fails_at(R"("velocity": 2)", R"("velocty": 2)", "dh.joints[0].limits.velocty");
  fails_at(R"("lower": -2)", R"("lower": 3)", "dh.joints[0].limits");
  fails_at(R"("type": "prismatic")", R"("type": "screw")", "dh.joints[1].type");
  fails_at(R"("m": 1,)", R"("m": -1,)", "dh.joints[1].inertial.m");
  fails_at(R"("dh": {)", R"("bodies": [], "dh": {)", "");
  fails_at(R"(["fv", "fc", "fo"])", R"(["fv", "fx", "fo"])", "drive_terms");
  fails_at(R"(["fv", "fc", "fo"])", R"(["fv", 3])", "drive_terms[1]");
  fails_at(R"("drive_terms": ["fv", "fc", "fo"])", R"("drives": true, "offsets": true)", "offsets");
  fails_at(R"("Fo": -0.25)", R"("Fo": NaN)", "");  // not JSON: a parse error of the file
  fails_at(R"("Fo": -0.25)", R"("F0": -0.25)", "dh.joints[0].drive.F0");
}

TEST(Dh, QuarterTurnsAreExact) {
  for (int k = -4; k <= 4; ++k) {
    const Eigen::Matrix3d r = dhRotationX(k * kPi / 2);
    for (int i = 0; i < 9; ++i) {
      const double x = r.data()[i];
      EXPECT_TRUE(x == 0.0 || x == 1.0 || x == -1.0) << k << " " << x;
    }
  }
  // Off a quarter turn, the ordinary cosine.
  EXPECT_EQ(dhRotationZ(0.3)(0, 0), std::cos(0.3));
  // Any finite angle gives a rotation, also one beyond an int's range of quarter turns (the model
  // JSON fuzzer's alpha of -1.16e17 rad once converted it to int: undefined behaviour).
  for (double angle : {-115707963627948966.0, 1e300, 4e9 * kPi}) {
    const Eigen::Matrix3d r = dhRotationX(angle);
    EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-15) << angle;
    EXPECT_EQ(r(1, 1), std::cos(angle)) << angle;
  }
}

}  // namespace
}  // namespace dynid
