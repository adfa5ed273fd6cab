// Floating-base inverse dynamics, mass matrix and forward dynamics, against the same robot with
// its free flyer as six virtual joints through the fixed-base RNEA (tests/common/floating_models).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "core/floating/floating_rnea-inl.hpp"
#include "core/rnea.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

// Round-off of a few hundred flops on torques of order 10-100 N m: 1e-12 relative is ~1e4 ulp.
constexpr double kTolerance = 1e-12;

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / std::max(1.0, b.norm());
}

class FloatingRneaOnTrees : public ::testing::TestWithParam<int> {};

/// Over `trials` random states: the joints' torques are the virtual chain's; the base wrench is
/// the force the chain's sixth joint transmits into the base body (its joint frame is the base
/// frame).
void expectTheChainsRnea(const FloatingModel& model, std::uint64_t seed, int trials) {
  const Model chain = test::virtualChain(model);
  FloatingData data(model);
  Data chain_data(chain);
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < trials; ++trial) {
    const test::FloatingSample s = test::randomFloatingSample(model, chain, rng);
    const Eigen::VectorXd tau = floatingRnea(model, data, s.base, s.q, s.dq, s.ddq);
    const Eigen::VectorXd chain_tau = rnea(chain, chain_data, s.chain_q, s.chain_dq, s.chain_ddq);
    EXPECT_LT(relative(tau.tail(model.numJoints()), chain_tau.tail(model.numJoints())), kTolerance);
    EXPECT_LT(relative(tau.head<6>(), chain_data.f[5]), kTolerance);
  }
}

TEST_P(FloatingRneaOnTrees, EqualsTheVirtualChainsFixedBaseRnea) {
  expectTheChainsRnea(test::randomFloating(GetParam(), {.num_bodies = 8}), GetParam(), 20);
}

/// The example robots through the same check: half of ANYmal C's joints turn about -e_x, which the
/// floating kernels take on the unit axis' fast path (the chain's fixed-base RNEA by the general
/// axis' spatial algebra).
TEST(FloatingRnea, OnTheExampleRobotsEqualsTheVirtualChainsFixedBaseRnea) {
  for (const test::FloatingExample* example : {&test::kAnymalExample, &test::kRomeoExample})
    expectTheChainsRnea(test::loadExample(*example), 7, 10);
  const FloatingModel anymal = test::loadExample(test::kAnymalExample);
  EXPECT_EQ(std::count(anymal.axisSigns().begin(), anymal.axisSigns().end(), -1), 6);
}

TEST_P(FloatingRneaOnTrees, MassMatrixAndBiasGiveTheInverseDynamics) {
  FloatingModel model = test::randomFloating(GetParam(), {.num_bodies = 7, .drives = true});
  FloatingData data(model);
  std::mt19937_64 rng(GetParam() + 7);
  const int n = model.numJoints();
  for (int trial = 0; trial < 10; ++trial) {
    BaseMotion base;
    base.rotation = rotationFromRpy(0.3 * trial, -0.2, 0.7);
    base.twist = test::randomVector(rng, 6, 1.0);
    const Eigen::VectorXd q = test::randomVector(rng, n, 2.0), dq = test::randomVector(rng, n, 1.5);
    const Eigen::VectorXd acc = test::randomVector(rng, 6 + n, 3.0);
    base.acceleration = acc.head<6>();
    const Eigen::VectorXd full = floatingRnea(model, data, base, q, dq, acc.tail(n));
    BaseMotion still = base;
    still.acceleration.setZero();
    const Eigen::VectorXd h = floatingRnea(model, data, still, q, dq, Eigen::VectorXd::Zero(n));
    const Eigen::MatrixXd M = floatingCrba(model, data, q);
    EXPECT_LT(relative(M * acc + h, full), kTolerance);
    EXPECT_LT((M - M.transpose()).norm(), 1e-14 * M.norm());  // both triangles written alike
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(M).info(), Eigen::Success);  // positive definite
    // The base block is the whole robot's composite inertia: its mass is the total mass.
    double mass = model.baseInertia().mass;
    for (const RigidInertia<double>& I : model.limbs().inertias()) mass += I.mass;
    EXPECT_NEAR(M(3, 3), mass, 1e-12 * mass);
    // Forward dynamics inverts it: the accelerations that make the torques and wrench given.
    const Eigen::VectorXd back =
        floatingForwardDynamics(model, data, base, q, dq, full.tail(n), full.head<6>());
    EXPECT_LT(relative(back, acc), 1e-10);  // through a Cholesky solve of a matrix of cond ~1e3
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, FloatingRneaOnTrees, ::testing::Values(1, 2, 3, 4));

TEST(FloatingRnea, ARobotAtRestInGravityNeedsItsWeightAtTheBase) {
  const FloatingModel model = test::randomFloating(5, {.num_bodies = 5});
  FloatingData data(model);
  const int n = model.numJoints();
  BaseMotion base;
  base.rotation = rotationFromRpy(0.4, -0.3, 1.1);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  const Eigen::VectorXd tau = floatingRnea(model, data, base, q, zero, zero);
  // At rest the base force is -m g in base axes (the support carries the weight).
  const double mass = floatingCrba(model, data, q)(3, 3);
  const Eigen::Vector3d force = base.rotation * tau.segment<3>(3);
  EXPECT_LT((force + mass * model.gravity()).norm(), 1e-12 * mass * 9.81);
}

TEST(FloatingRnea, InFreeFallTheCentreOfMassFallsWithGravity) {
  // No wrench on the base: the whole body's centre of mass accelerates with g, whatever the
  // joint torques do (checked through the momentum's rate, the base block's first moment).
  const FloatingModel model = test::randomFloating(6, {.num_bodies = 6});
  FloatingData data(model);
  const int n = model.numJoints();
  std::mt19937_64 rng(6);
  BaseMotion base;
  base.rotation = rotationFromRpy(-0.5, 0.2, 0.3);
  base.twist = test::randomVector(rng, 6, 1.0);
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 1.0);
  const Eigen::VectorXd torque = test::randomVector(rng, n, 5.0);
  const Eigen::VectorXd acc =
      floatingForwardDynamics(model, data, base, q, dq, torque, Vector6<double>::Zero());
  base.acceleration = acc.head<6>();
  const Eigen::VectorXd tau = floatingRnea(model, data, base, q, dq, acc.tail(n));
  EXPECT_LT(tau.head<6>().norm(), 1e-9);
  EXPECT_LT(relative(tau.tail(n), torque), 1e-10);
}

TEST(FloatingRnea, JetDerivativesEqualFiniteDifferences) {
  using Jet = ceres::Jet<double, 4>;
  const FloatingModel model = test::randomFloating(8, {.num_bodies = 4});
  const FloatingModelTpl<Jet> jet_model = model.cast<Jet>();
  FloatingDataTpl<Jet> jet_data(jet_model);
  FloatingData data(model);
  std::mt19937_64 rng(8);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 1.0);
  const Eigen::VectorXd ddq = test::randomVector(rng, n, 1.0);
  BaseMotion base;
  base.twist = test::randomVector(rng, 6, 1.0);
  base.acceleration = test::randomVector(rng, 6, 1.0);
  BaseMotionTpl<Jet> jet_base;
  for (int k = 0; k < 6; ++k)
    jet_base.twist[k] = Jet(base.twist[k]), jet_base.acceleration[k] = Jet(base.acceleration[k]);
  VectorX<Jet> jq(n), jdq(n), jddq(n);
  for (int i = 0; i < n; ++i) jq[i] = Jet(q[i], i), jdq[i] = Jet(dq[i]), jddq[i] = Jet(ddq[i]);
  const VectorX<Jet> jtau = floatingRnea(jet_model, jet_data, jet_base, jq, jdq, jddq);
  const Eigen::VectorXd tau = floatingRnea(model, data, base, q, dq, ddq);
  const double h = 1e-6;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += h, qm[i] -= h;
    const Eigen::VectorXd up = floatingRnea(model, data, base, qp, dq, ddq);
    const Eigen::VectorXd down = floatingRnea(model, data, base, qm, dq, ddq);
    const Eigen::VectorXd fd = (up - down) / (2 * h);
    for (int r = 0; r < 6 + n; ++r) {
      EXPECT_NEAR(jtau[r].a, tau[r], 1e-12 * std::max(1.0, std::abs(tau[r])));
      // Central differences at h = 1e-6: truncation ~h^2 and round-off ~1e-16/h of the scale.
      EXPECT_NEAR(jtau[r].v[i], fd[r], 1e-6 * std::max(1.0, std::abs(fd[r])));
    }
  }
}

TEST(FloatingRnea, RefusesMismatchedSizesAndAnotherModelsData) {
  const FloatingModel model = test::randomFloating(9, {.num_bodies = 4});
  const FloatingModel other = test::randomFloating(9, {.num_bodies = 5});
  FloatingData data(model), other_data(other);
  const Eigen::VectorXd four = Eigen::VectorXd::Zero(4), three = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(floatingRnea(model, data, BaseMotion{}, three, four, four), InputError);
  EXPECT_THROW(floatingRnea(model, other_data, BaseMotion{}, four, four, four), InputError);
  EXPECT_THROW(floatingCrba(model, data, three), InputError);
  EXPECT_THROW(floatingForwardDynamics(model, data, BaseMotion{}, four, four, three,
                                       Vector6<double>::Zero()),
               InputError);
}

}  // namespace
}  // namespace dynid
