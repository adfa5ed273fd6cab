#include "reports/payload_report.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/payload/body.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/payload_record.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/json_number.hpp"

namespace dynid {
namespace {

/// Every number in `text` after `from`, in order: each maximal run that strtod reads, starting at
/// a digit, a sign or a point.
std::vector<double> numbersIn(const std::string& text, std::size_t from = 0) {
  std::vector<double> out;
  const char* p = text.c_str() + from;
  while (*p != '\0') {
    const bool starts =
        std::isdigit(static_cast<unsigned char>(*p)) ||
        ((*p == '-' || *p == '+' || *p == '.') && std::isdigit(static_cast<unsigned char>(p[1])));
    if (!starts) {
      ++p;
      continue;
    }
    char* end = nullptr;
    out.push_back(std::strtod(p, &end));
    p = end;
  }
  return out;
}

/// The outcome's body fields from a principal body (what payloadRun derives from `standard`).
PayloadOutcome outcomeOf(const PrincipalBody& body) {
  PayloadOutcome o;
  o.robot = "arm";
  o.link_name = "link6";
  o.setBody(standardFromPrincipal(body));
  return o;
}

/// The hand-computed case: 2 kg, centre of mass 100 mm along x, principal moments 0.01, 0.02,
/// 0.03 kg m^2 about axes turned 30 degrees about z.
PayloadOutcome handCase() {
  PrincipalBody b;
  b.mass = 2.0;
  b.com = Eigen::Vector3d(0.1, 0.0, 0.0);
  b.moments = Eigen::Vector3d(0.01, 0.02, 0.03);
  b.axes = rotationFromRpy(0.0, 0.0, M_PI / 6);
  return outcomeOf(b);
}

TEST(PayloadReport, EachControllersConventionByHand) {
  const PayloadOutcome o = handCase();
  // UR: inertia about the COM in flange axes [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]: R diag(a, b) R^T with
  // c = cos 30, s = sin 30: Ixx = a c^2 + b s^2 = 0.0125, Iyy = a s^2 + b c^2 = 0.0175,
  // Ixy = (a - b) s c = -0.004330127.
  const auto ur = payloadVendorFile(o, "ur");
  EXPECT_EQ(ur.first, "payload.urscript");
  const std::vector<double> u = numbersIn(ur.second, ur.second.find("set_target_payload("));
  const std::vector<double> u_expected = {2, 0.1, 0, 0, 0.0125, 0.0175, 0.03, -0.004330127, 0, 0};
  ASSERT_EQ(u.size(), u_expected.size()) << ur.second;
  for (std::size_t k = 0; k < u.size(); ++k) EXPECT_NEAR(u[k], u_expected[k], 1e-9) << k;
  // KUKA: mm, the principal axes as A = 30 deg about z, B = C = 0, J = the principal moments.
  const auto kuka = payloadVendorFile(o, "kuka");
  EXPECT_NE(kuka.second.find("LOAD_DATA[1]={M 2,CM {X 100,Y 0,Z 0,A 30,B 0,C 0},J {X 0.01,Y "
                             "0.02,Z 0.03}}"),
            std::string::npos)
      << kuka.second;
  // ABB: mm, the quaternion (cos 15 deg, 0, 0, sin 15 deg) with q1 the scalar part.
  const auto abb = payloadVendorFile(o, "abb");
  EXPECT_NE(abb.second.find("PERS loaddata dynid_payload := [2,[100,0,0],[0.9659258,0,0,"
                            "0.258819],0.01,0.02,0.03];"),
            std::string::npos)
      << abb.second;
  // Franka: F_x_Cload in m, I_load column-major about the COM.
  const auto franka = payloadVendorFile(o, "franka");
  const auto f = nlohmann::json::parse(franka.second);
  EXPECT_DOUBLE_EQ(f["load_mass"].get<double>(), 2.0);
  EXPECT_NEAR(f["F_x_Cload"][0].get<double>(), 0.1, 1e-15);
  EXPECT_NEAR(f["load_inertia"][1].get<double>(), -0.004330127018922193, 1e-15);  // (1, 0)
  EXPECT_NEAR(f["load_inertia"][4].get<double>(), 0.0175, 1e-15);
  EXPECT_THROW(payloadVendorFile(o, "fanuc"), InputError);
}

TEST(PayloadReport, EveryConventionRoundTripsToTheSameBody) {
  PrincipalBody b;  // asymmetric, turned about every axis, off-centre
  b.mass = 3.7;
  b.com = Eigen::Vector3d(0.021, -0.113, 0.064);
  b.moments = Eigen::Vector3d(0.031, 0.017, 0.024);
  b.axes = rotationFromKukaAbc(Eigen::Vector3d(0.7, -0.4, 1.1));
  const PayloadOutcome o = outcomeOf(b);
  const Eigen::Matrix<double, 10, 1> truth = o.standard;
  // 7 significant digits in the controllers' files: 1e-6 relative.
  const double tolerance = 1e-6 * truth.norm();
  {
    const std::string t = payloadVendorFile(o, "ur").second;
    const std::vector<double> v = numbersIn(t, t.find("set_target_payload("));
    ASSERT_EQ(v.size(), 10u);
    RigidInertia<double> r;
    r.mass = v[0];
    r.first_moment = v[0] * Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Matrix3d ic;
    ic << v[4], v[7], v[8], v[7], v[5], v[9], v[8], v[9], v[6];
    const Eigen::Matrix3d sc = skew(Eigen::Vector3d(v[1], v[2], v[3]));
    r.inertia = ic - v[0] * sc * sc;
    EXPECT_LT((toStandardVector(r) - truth).norm(), tolerance) << t;
  }
  {
    const std::string t = payloadVendorFile(o, "kuka").second;
    const std::vector<double> v = numbersIn(t, t.find("LOAD_DATA[1]=") + 13);
    ASSERT_EQ(v.size(), 10u);
    PrincipalBody p;
    p.mass = v[0];
    p.com = Eigen::Vector3d(v[1], v[2], v[3]) * 1e-3;
    p.axes = rotationFromKukaAbc(Eigen::Vector3d(v[4], v[5], v[6]) * M_PI / 180.0);
    p.moments = Eigen::Vector3d(v[7], v[8], v[9]);
    EXPECT_LT((standardFromPrincipal(p) - truth).norm(), tolerance) << t;
  }
  {
    const std::string t = payloadVendorFile(o, "abb").second;
    const std::vector<double> v = numbersIn(t, t.find(":= ["));
    ASSERT_EQ(v.size(), 11u);
    PrincipalBody p;
    p.mass = v[0];
    p.com = Eigen::Vector3d(v[1], v[2], v[3]) * 1e-3;
    p.axes = rotationFromAbbQuaternion(Eigen::Vector4d(v[4], v[5], v[6], v[7]));
    p.moments = Eigen::Vector3d(v[8], v[9], v[10]);
    EXPECT_LT((standardFromPrincipal(p) - truth).norm(), tolerance) << t;
  }
  {
    const auto f = nlohmann::json::parse(payloadVendorFile(o, "franka").second);
    RigidInertia<double> r;
    r.mass = f["load_mass"].get<double>();
    const Eigen::Vector3d c(f["F_x_Cload"][0].get<double>(), f["F_x_Cload"][1].get<double>(),
                            f["F_x_Cload"][2].get<double>());
    Eigen::Matrix3d ic;
    for (int k = 0; k < 9; ++k) ic(k % 3, k / 3) = f["load_inertia"][k].get<double>();
    r.first_moment = r.mass * c;
    r.inertia = ic - r.mass * skew(c) * skew(c);
    EXPECT_LT((toStandardVector(r) - truth).norm(), 1e-14 * truth.norm());
  }
  {  // dynid's own: read back exactly by --prior
    const auto j = nlohmann::json::parse(payloadVendorFile(o, "json").second);
    EXPECT_EQ(j["kind"], kPayloadBodyDocument.kind);
    EXPECT_EQ(payloadBodyFrom(j, "body.json"), truth);
  }
}

TEST(PayloadReport, ControllerFilesHoldNoInputAsCode) {
  PayloadOutcome o = handCase();
  o.robot = "arm\n set_target_payload(99, [0,0,0])";
  o.link_name = "l\r\n! PERS x := 1;";
  for (const std::string& format : payloadFormats()) {
    const std::string text = payloadVendorFile(o, format).second;
    if (format == "franka" || format == "json") continue;  // JSON strings are escaped
    // One comment line, then the one statement: the names stay inside the comment.
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
    const std::string second = text.substr(text.find('\n') + 1);
    EXPECT_TRUE(second.rfind("set_target_payload(2, ", 0) == 0 ||
                second.rfind("LOAD_DATA[1]={M 2,", 0) == 0 ||
                second.rfind("PERS loaddata dynid_payload := [2,", 0) == 0)
        << text;
  }
}

TEST(PayloadReport, ThePayloadDocumentNamesItsKindAndReadsBackAsAPrior) {
  const PayloadOutcome o = handCase();
  const nlohmann::json j = payloadJson(o);
  EXPECT_EQ(j["kind"], kPayloadDocument.kind);
  EXPECT_EQ(j["schema_version"], kPayloadDocument.schema_version);
  EXPECT_EQ(payloadBodyFrom(j, "payload.json"), o.standard);
  nlohmann::json other = j;
  other["kind"] = "dynid.estimate";
  EXPECT_THROW(payloadBodyFrom(other, "x.json"), ParseError);
  other = j;
  other["standard"].erase("Iyz");
  try {
    payloadBodyFrom(other, "x.json");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("standard.Iyz"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
