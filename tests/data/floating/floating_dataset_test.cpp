// Floating-base datasets (data/floating/floating_dataset.hpp): written and read back exactly, in
// any column order, and every malformed file refused with its line, its column and what is wrong.
#include "data/floating/floating_dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "core/errors.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/format.hpp"
#include "data/urdf.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

const FloatingModel& anymal() {
  static const FloatingModel model =
      loadFloatingUrdf(std::string(DYNID_SOURCE_DIR) + "/examples/floating/anymal_c/anymal.urdf");
  return model;
}

/// Random signals: a point force at LF_FOOT, a wrench at RF_FOOT, flags at both.
FloatingDataset randomDataset(int samples) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto random = [&](Eigen::Index rows) {
    Eigen::MatrixXd m(rows, samples);
    for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = normal(rng);
    return m;
  };
  FloatingDataset d;
  d.joints = anymal().limbs().joint_names;
  const Eigen::Index n = static_cast<Eigen::Index>(d.joints.size());
  d.time = Eigen::VectorXd::LinSpaced(samples, 0.0, 0.01 * (samples - 1));
  d.orientation = random(4);
  d.orientation.colwise().normalize();
  d.twist = random(6);
  d.acceleration = random(6);
  d.q = random(n);
  d.dq = random(n);
  d.ddq = random(n);
  d.tau = random(n);
  d.wrenches = {{"LF_FOOT", random(3)}, {"RF_FOOT", random(6)}};
  d.flags = {{"LF_FOOT", std::vector<char>(static_cast<std::size_t>(samples), 1)},
             {"RF_FOOT", std::vector<char>(static_cast<std::size_t>(samples), 0)}};
  return d;
}

TEST(FloatingDataset, WrittenAndReadBackExactly) {
  const FloatingDataset d = randomDataset(20);
  const std::string path = test::tempPath("floating.csv");
  writeFloatingDataset(path, d);
  const FloatingDataset back = readFloatingDataset(path, anymal());
  EXPECT_EQ(back.joints, d.joints);
  EXPECT_EQ(back.time, d.time);
  // Normalised again on reading: a unit quaternion's norm is 1 within a rounding or two.
  EXPECT_LT((back.orientation - d.orientation).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(back.twist, d.twist);
  EXPECT_EQ(back.acceleration, d.acceleration);
  EXPECT_EQ(back.q, d.q);
  EXPECT_EQ(back.dq, d.dq);
  EXPECT_EQ(back.ddq, d.ddq);
  EXPECT_EQ(back.tau, d.tau);
  ASSERT_EQ(back.wrenches.size(), 2u);
  EXPECT_EQ(back.findWrench("LF_FOOT")->values, d.wrenches[0].values);
  EXPECT_EQ(back.findWrench("RF_FOOT")->values, d.wrenches[1].values);
  EXPECT_EQ(back.findFlag("LF_FOOT")->holding, d.flags[0].holding);
  EXPECT_EQ(back.findFlag("RF_FOOT")->holding, d.flags[1].holding);
  EXPECT_EQ(back.line(0), 2);
}

/// The file with its columns in reverse order: read the same.
TEST(FloatingDataset, ColumnsInAnyOrder) {
  const FloatingDataset d = randomDataset(5);
  const std::string path = test::tempPath("floating_order.csv");
  writeFloatingDataset(path, d);
  std::ifstream in(path);
  std::string line, reversed;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) fields.insert(fields.begin(), f);
    for (std::size_t k = 0; k < fields.size(); ++k) reversed += (k ? "," : "") + fields[k];
    reversed += "\n";
  }
  const std::string other = test::tempPath("floating_reversed.csv");
  std::ofstream(other) << reversed;
  const FloatingDataset back = readFloatingDataset(other, anymal());
  EXPECT_EQ(back.q, d.q);
  EXPECT_EQ(back.findWrench("RF_FOOT")->values, d.wrenches[1].values);
}

TEST(FloatingDataset, WithoutTorquesOrContacts) {
  FloatingDataset d = randomDataset(3);
  d.tau.resize(0, 3);
  d.wrenches.clear();
  d.flags.clear();
  const std::string path = test::tempPath("floating_bare.csv");
  writeFloatingDataset(path, d);
  const FloatingDataset back = readFloatingDataset(path, anymal());
  EXPECT_FALSE(back.hasTorques());
  EXPECT_TRUE(back.wrenches.empty());
}

/// The error of reading `text` after editing the written file of randomDataset(3): its message.
std::string errorOf(const std::function<void(std::string&)>& edit) {
  const std::string path = test::tempPath("floating_bad.csv");
  writeFloatingDataset(path, randomDataset(3));
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  edit(text);
  std::ofstream(path) << text;
  try {
    readFloatingDataset(path, anymal());
  } catch (const ParseError& e) {
    return e.what();
  }
  return "no error";
}

void replaceFirst(std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

TEST(FloatingDataset, AWrenchInAnUnknownFrameIsNamed) {
  const std::string e = errorOf([](std::string& t) {
    for (const char* c : {"fx", "fy", "fz"})
      replaceFirst(t, std::string("wrench:LF_FOOT:") + c, std::string("wrench:LF_TOE:") + c);
  });
  EXPECT_TRUE(test::contains(e, ".csv:1:")) << e;
  EXPECT_TRUE(test::contains(e, "'LF_TOE' is no frame of 'anymal'")) << e;
  EXPECT_TRUE(test::contains(e, "LF_FOOT")) << e;  // the frames there are
}

TEST(FloatingDataset, HeadersThatDoNotFitTheModelAreRefused) {
  EXPECT_TRUE(
      test::contains(errorOf([](std::string& t) { replaceFirst(t, "q:LF_HAA", "q:LF_XXX"); }),
                     "'LF_XXX' is no joint of 'anymal'"));
  EXPECT_TRUE(test::contains(errorOf([](std::string& t) { replaceFirst(t, "ddq:LF_HAA", "t"); }),
                             "appears twice"));
  EXPECT_TRUE(
      test::contains(errorOf([](std::string& t) { replaceFirst(t, "tau:LF_HAA", "speed:LF_HAA"); }),
                     "unknown column 'speed:LF_HAA'"));
  EXPECT_TRUE(test::contains(
      errorOf([](std::string& t) { replaceFirst(t, "wrench:LF_FOOT:fy", "wrench:LF_FOOT:gy"); }),
      "unknown wrench component 'gy'"));
  EXPECT_TRUE(test::contains(
      errorOf([](std::string& t) { replaceFirst(t, "wrench:RF_FOOT:ny", "contact:LH_FOOT"); }),
      "lacks the column 'wrench:RF_FOOT:ny'"));
  EXPECT_TRUE(test::contains(
      errorOf([](std::string& t) { replaceFirst(t, "base:dvz", "contact:RH_FOOT"); }),
      "lacks the column 'base:dvz'"));
}

TEST(FloatingDataset, BadRowsAreNamedByLineAndColumn) {
  // The second row's first field (t) replaced.
  const auto second_row = [](std::string& t, const std::string& field) {
    const std::size_t row = t.find('\n', t.find('\n') + 1) + 1;
    t.replace(row, t.find(',', row) - row, field);
  };
  std::string e = errorOf([&](std::string& t) { second_row(t, "-1"); });
  EXPECT_TRUE(test::contains(e, ".csv:3:") && test::contains(e, "does not increase")) << e;
  e = errorOf([&](std::string& t) { second_row(t, "x"); });
  EXPECT_TRUE(test::contains(e, ".csv:3:") && test::contains(e, "'x' is not a finite number")) << e;
  e = errorOf([](std::string& t) { t += "1,2\n"; });
  EXPECT_TRUE(test::contains(e, ".csv:5:") && test::contains(e, "row has 2 fields")) << e;
  e = errorOf([](std::string& t) { t = t.substr(0, t.find('\n') + 1); });
  EXPECT_TRUE(test::contains(e, "no sample")) << e;
}

TEST(FloatingDataset, AQuaternionThatIsNotUnitIsRefusedWithItsNorm) {
  FloatingDataset d = randomDataset(3);
  d.orientation.col(1) *= 1.01;
  const std::string path = test::tempPath("floating_quaternion.csv");
  writeFloatingDataset(path, d);
  try {
    readFloatingDataset(path, anymal());
    FAIL() << "no error";
  } catch (const ParseError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(test::contains(what, ".csv:3:") && test::contains(what, "base:qw") &&
                test::contains(what, "norm 1.01"))
        << what;
  }
  // Within 1e-3 of unit (single-precision logs): normalised.
  d.orientation.col(1) /= 1.01 / 1.0005;
  writeFloatingDataset(path, d);
  EXPECT_NEAR(readFloatingDataset(path, anymal()).orientation.col(1).norm(), 1.0, 1e-15);
}

TEST(FloatingDataset, AFlagIsZeroOrOne) {
  FloatingDataset d = randomDataset(3);
  const std::string path = test::tempPath("floating_flag.csv");
  writeFloatingDataset(path, d);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The last field of the first row is RF_FOOT's flag (0).
  const std::size_t end = text.find('\n', text.find('\n') + 1);
  text.replace(end - 1, 1, "2");
  std::ofstream(path) << text;
  try {
    readFloatingDataset(path, anymal());
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_TRUE(test::contains(e.what(), "contact:RF_FOOT") &&
                test::contains(e.what(), "a contact flag is 0 or 1, not 2"))
        << e.what();
  }
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

/// A smooth base motion recorded by the IMU on ANYmal's imu_link (off the base origin, rotated):
/// the motion read from it gives the inverse dynamics of the true twist and its derivative (the
/// base's linear velocity does not enter the forces, given its origin's acceleration).
TEST(FloatingDatasetImu, TheBaseMotionFromAnImuGivesTheSameDynamics) {
  const FloatingModel& model = anymal();
  const Pose<double>& F = model.findFrame("imu_link")->placement;
  const int n = model.numJoints(), N = 201;
  const double dt = 1e-3;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd q(n, N), dq(n, N), ddq(n, N);
  for (Eigen::Index k = 0; k < q.size(); ++k)
    q.data()[k] = u(rng), dq.data()[k] = u(rng), ddq.data()[k] = u(rng);
  std::vector<BaseMotion> truth;
  std::string text = "t,base:qw,base:qx,base:qy,base:qz";
  for (const char* c : {"wx", "wy", "wz", "ax", "ay", "az"})
    text += std::string(",imu:imu_link:") + c;
  for (const char* block : {"q:", "dq:", "ddq:"})
    for (const std::string& j : model.limbs().joint_names) text += "," + std::string(block) + j;
  text += "\n";
  for (int k = 0; k < N; ++k) {
    const double t = k * dt;
    BaseMotion b;
    b.rotation = rotationFromRpy(0.1 * std::sin(t), 0.2 * t, 0.3);
    const Eigen::Vector3d w(0.5 * std::sin(2 * t), 0.3 * std::cos(3 * t), 0.2 * std::sin(t));
    const Eigen::Vector3d dw(std::cos(2 * t), -0.9 * std::sin(3 * t), 0.2 * std::cos(t));
    const Eigen::Vector3d v(0.4 * std::cos(t), 0.1 * t, -0.2 * std::sin(2 * t));
    const Eigen::Vector3d dv(-0.4 * std::sin(t), 0.1, -0.4 * std::cos(2 * t));
    b.twist << w, v;
    b.acceleration << dw, dv;
    truth.push_back(b);
    // The IMU point's classical acceleration, then the specific force and rate in its axes.
    const Eigen::Vector3d origin = dv + w.cross(v), r = F.translation;
    const Eigen::Vector3d at_imu = origin + dw.cross(r) + w.cross(w.cross(r));
    const Eigen::Vector3d specific =
        F.rotation.transpose() * (at_imu - b.rotation.transpose() * model.gravity());
    const Eigen::Vector3d gyro = F.rotation.transpose() * w;
    const Eigen::Quaterniond o(b.rotation);
    text += formatNumber(t);
    for (double x : {o.w(), o.x(), o.y(), o.z()}) text += "," + formatNumber(x);
    for (int c = 0; c < 3; ++c) text += "," + formatNumber(gyro[c]);
    for (int c = 0; c < 3; ++c) text += "," + formatNumber(specific[c]);
    for (const Eigen::MatrixXd* m : {&q, &dq, &ddq})
      for (int j = 0; j < n; ++j) text += "," + formatNumber((*m)(j, k));
    text += "\n";
  }
  const std::string path = test::tempPath("floating_imu.csv");
  std::ofstream(path) << text;
  const FloatingDataset d = readFloatingDataset(path, model);
  EXPECT_EQ(d.imu_frame, "imu_link");
  FloatingData data(model);
  // The ends take one-sided differences (first order in dt): compared inside.
  for (int k = 1; k + 1 < N; ++k) {
    BaseMotion read;
    read.rotation = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    read.twist = d.twist.col(k);
    read.acceleration = d.acceleration.col(k);
    EXPECT_TRUE(read.twist.tail<3>().isZero());
    const Eigen::VectorXd expected = floatingRnea(model, data, truth[static_cast<std::size_t>(k)],
                                                  q.col(k), dq.col(k), ddq.col(k));
    const Eigen::VectorXd got = floatingRnea(model, data, read, q.col(k), dq.col(k), ddq.col(k));
    // The three-point derivative of omega errs by dt^2 / 6 |omega'''| ~ 1e-6 rad/s^2 at dt = 1 ms;
    // times the robot's inertia, a millionth of the forces and torques.
    EXPECT_LT((got - expected).norm() / expected.norm(), 1e-6) << "sample " << k;
  }
}

TEST(FloatingDatasetImu, AnImuOnALimbOrBesideTheBaseColumnsIsRefused) {
  const std::string path = test::tempPath("floating_imu_bad.csv");
  writeFloatingDataset(path, randomDataset(3));
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The twist columns renamed as an IMU's: the derivative's base: columns remain.
  std::string both = text;
  for (const char* c : {"wx", "wy", "wz"})
    replaceFirst(both, std::string("base:") + c, std::string("imu:imu_link:") + c);
  replaceFirst(both, "base:vx", "imu:imu_link:ax");
  replaceFirst(both, "base:vy", "imu:imu_link:ay");
  replaceFirst(both, "base:vz", "imu:imu_link:az");
  std::ofstream(path) << both;
  try {
    readFloatingDataset(path, anymal());
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_TRUE(test::contains(e.what(), "from base: columns and from an IMU: give one"))
        << e.what();
  }
  std::string limb = both;
  for (const char* c : {"wx", "wy", "wz", "ax", "ay", "az"})
    replaceFirst(limb, std::string("imu:imu_link:") + c, std::string("imu:LF_SHANK:") + c);
  std::ofstream(path) << limb;
  try {
    readFloatingDataset(path, anymal());
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_TRUE(test::contains(e.what(), "'LF_SHANK' is on a limb")) << e.what();
  }
}

}  // namespace
}  // namespace dynid
