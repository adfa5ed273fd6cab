#include "data/mjcf.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/aba.hpp"
#include "core/format.hpp"
#include "core/integrators.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

#ifdef DYNID_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace dynid {
namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Mjcf, OneBodyAndJointPerDynidJoint) {
  const Model model = test::randomTree(3);
  const std::string text = modelToMjcf(model, {.timestep = 2e-3, .integrator = "Euler"});
  EXPECT_EQ(count(text, "<body "), model.numJoints());
  EXPECT_EQ(count(text, "<joint "), model.numJoints());
  EXPECT_EQ(count(text, "<inertial "), model.numJoints());
  EXPECT_EQ(count(text, "type=\"slide\""), [&] {
    int n = 0;
    for (JointType t : model.joint_types()) n += t == JointType::kPrismatic;
    return n;
  }());
  EXPECT_NE(text.find("timestep=\"0.002\" integrator=\"Euler\""), std::string::npos);
  EXPECT_NE(text.find("gravity=\""), std::string::npos);
  // Nesting follows the tree: as many closing tags as bodies.
  EXPECT_EQ(count(text, "</body>"), model.numJoints());
}

TEST(Mjcf, WithItsDrivesJointsCarryArmatureDampingFrictionlossAndRanges) {
  const Model puma = makePuma560(true);  // ia, fv, fc, fa
  // By default rigid-body dynamics only (the peer benchmarks'): no drive, no range.
  EXPECT_EQ(count(modelToMjcf(puma), "limited=\"false\" damping=\"0\" armature=\"0\""), 6);
  const std::string text = modelToMjcf(puma, {.drives_and_limits = true});
  const std::string first = text.substr(
      text.find("<joint "), text.find("/>", text.find("<joint ")) - text.find("<joint "));
  const DriveParameters<double>& d = puma.drives()[0];
  EXPECT_NE(first.find("armature=\"" + formatNumber(d[DriveTerm::kRotorInertia]) + "\""),
            std::string::npos)
      << first;
  EXPECT_NE(first.find("damping=\"" + formatNumber(d[DriveTerm::kViscous]) + "\""),
            std::string::npos)
      << first;
  EXPECT_NE(first.find("frictionloss=\"" + formatNumber(d[DriveTerm::kCoulomb]) + "\""),
            std::string::npos)
      << first;
  EXPECT_NE(first.find("limited=\"true\" range=\"" + formatNumber(puma.limits[0].lower) + " " +
                       formatNumber(puma.limits[0].upper) + "\""),
            std::string::npos)
      << first;
  // What it cannot carry: the Coulomb asymmetry, and link 1's zero mass (MuJoCo refuses it).
  const std::vector<std::string> notes = mjcfCannotCarry(puma);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("Coulomb asymmetry (Fa)"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("link " + puma.link_names[0] + " has mass 0"), std::string::npos)
      << notes[1];
  EXPECT_TRUE(mjcfCannotCarry(makePuma560Consistent(false)).empty());
}

#ifdef DYNID_HAVE_MUJOCO
/// MuJoCo loads the exported text (through a temporary file); null and the error when it refuses.
mjModel* load(const std::string& text, std::string& error) {
  const std::string path = test::tempPath("model.xml");  // unique to this process and call
  std::ofstream(path) << text;
  char buffer[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, buffer, sizeof(buffer));
  std::filesystem::remove(path);
  error = buffer;
  return m;
}

// MuJoCo simulates the exported model with dynid's dynamics: inverse dynamics and one RK4 step
// agree to `tolerance` relative (MuJoCo's dofs permuted to dynid's order).
void expectSameDynamics(const Model& model, double tolerance) {
  std::string error;
  mjModel* m = load(modelToMjcf(model, {.timestep = 1e-3, .integrator = "RK4"}), error);
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  ASSERT_EQ(m->nv, model.numJoints());
  const int n = model.numJoints();
  const std::vector<int> order = mjcfJointOrder(model);
  Data data(model);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 2.0),
                          ddq = test::randomVector(rng, n, 2.0),
                          tau = test::randomVector(rng, n, 10.0);
    // MuJoCo's dof j is dynid's joint order[j].
    const auto to_mj = [&](const Eigen::VectorXd& v, mjtNum* out) {
      for (int j = 0; j < n; ++j) out[j] = v[order[j]];
    };
    const auto from_mj = [&](const mjtNum* in) {
      Eigen::VectorXd v(n);
      for (int j = 0; j < n; ++j) v[order[j]] = in[j];
      return v;
    };
    to_mj(q, d->qpos);
    to_mj(dq, d->qvel);
    to_mj(ddq, d->qacc);
    mj_inverse(m, d);
    const Eigen::VectorXd expected_tau = rnea(model, data, q, dq, ddq);
    EXPECT_LT((from_mj(d->qfrc_inverse) - expected_tau).norm(),
              tolerance * (1.0 + expected_tau.norm()))
        << "state " << k;
    to_mj(tau, d->qfrc_applied);
    d->time = 0.0;
    mj_step(m, d);
    Eigen::VectorXd q1 = q, dq1 = dq;
    rk4Step(model, data, q1, dq1, tau, 1e-3);
    EXPECT_LT((from_mj(d->qpos) - q1).norm(), tolerance * (1.0 + q1.norm())) << "state " << k;
    EXPECT_LT((from_mj(d->qvel) - dq1).norm(), tolerance * (1.0 + dq1.norm())) << "state " << k;
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}

TEST(Mjcf, MuJoCoSimulatesTheConsistentPumaLikeDynid) {
  // Diagonal inertias in the joint frames: round-off only (about 1e-14 measured).
  expectSameDynamics(makePuma560Consistent(), 1e-9);
}

TEST(Mjcf, MuJoCoSimulatesTreesWithGeneralAxesSlidesAndPlacementsLikeDynid) {
  // MuJoCo diagonalises each full inertia iteratively (mju_eig3): about 4e-9 relative measured.
  for (std::uint64_t seed : {11, 12, 13}) expectSameDynamics(test::randomTree(seed), 1e-7);
}

TEST(Mjcf, JointOrderIsDepthFirst) {
  Model model;  // base -> 0 -> {1, 2}, 1 -> 3: MuJoCo's order 0, 1, 3, 2
  const RigidInertia<double> body = test::randomTree(1).inertias()[0];
  model.addBody(-1, "a", "ja", JointType::kRevolute, {}, Eigen::Vector3d::UnitZ(), {}, body);
  model.addBody(0, "b", "jb", JointType::kRevolute, {}, Eigen::Vector3d::UnitY(), {}, body);
  model.addBody(0, "c", "jc", JointType::kRevolute, {}, Eigen::Vector3d::UnitY(), {}, body);
  model.addBody(1, "d", "jd", JointType::kRevolute, {}, Eigen::Vector3d::UnitX(), {}, body);
  model.finalize();
  EXPECT_EQ(mjcfJointOrder(model), (std::vector<int>{0, 1, 3, 2}));
  EXPECT_EQ(mjcfJointOrder(makePuma560()), (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(Mjcf, MuJoCoRefusesTheOriginalPumaNamingTheLink) {
  std::string error;
  mjModel* m = load(modelToMjcf(makePuma560()), error);
  EXPECT_EQ(m, nullptr);
  if (m != nullptr) mj_deleteModel(m);
  EXPECT_NE(error.find("link1"), std::string::npos) << error;
}
#else
TEST(Mjcf, MuJoCoComparisonSkipped) {
  GTEST_SKIP() << "MuJoCo (libmujoco-dev) not found at build time";
}
#endif

}  // namespace
}  // namespace dynid
