// Floating-base ABA (core/floating/floating_aba.hpp) against forward dynamics by the mass matrix
// (floatingForwardDynamics, itself checked against the virtual chain), on random trees with drive
// terms, the example robots, in free fall and pushed, and with ceres::Jet.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "core/floating/floating_aba-inl.hpp"
#include "core/floating/floating_rnea.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

/// Both solve the same linear system by different algebra (an O(n^3) Cholesky against recursive
/// articulated inertias): 1e-10 relative is ~1e6 ulp of accelerations of order 1-100 rad/s^2, the
/// mass matrix's conditioning on light distal bodies.
constexpr double kAbaTolerance = 1e-10;

void expectAbaEqualsTheMassMatrixSolve(const FloatingModel& model, std::uint64_t seed) {
  FloatingData data(model);
  std::mt19937_64 rng(seed);
  const int n = model.numJoints();
  for (int trial = 0; trial < 10; ++trial) {
    BaseMotion base;
    base.rotation = rotationFromRpy(0.4 * trial, -0.3, 0.9);
    base.twist = test::randomVector(rng, 6, 1.0);
    const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), dq = test::randomVector(rng, n, 1.5);
    const Eigen::VectorXd tau = test::randomVector(rng, n, 10.0);
    // Free fall, then a push on the base.
    const Vector6<double> wrench =
        trial % 2 ? Vector6<double>(test::randomVector(rng, 6, 20.0)) : Vector6<double>::Zero();
    const Eigen::VectorXd expected = floatingForwardDynamics(model, data, base, q, dq, tau, wrench);
    const Eigen::VectorXd got = floatingAba(model, data, base, q, dq, tau, wrench);
    EXPECT_LT((got - expected).norm() / std::max(1.0, expected.norm()), kAbaTolerance)
        << "trial " << trial;
  }
}

class FloatingAbaOnTrees : public ::testing::TestWithParam<int> {};

TEST_P(FloatingAbaOnTrees, EqualsTheMassMatrixSolve) {
  expectAbaEqualsTheMassMatrixSolve(test::randomFloating(GetParam(), {.num_bodies = 9}),
                                    GetParam());
}

TEST_P(FloatingAbaOnTrees, WithFrictionAndRotorInertia) {
  expectAbaEqualsTheMassMatrixSolve(
      test::randomFloating(GetParam() + 100, {.num_bodies = 7, .drives = true}), GetParam());
}

TEST_P(FloatingAbaOnTrees, OnAChain) {
  expectAbaEqualsTheMassMatrixSolve(
      test::randomFloating(GetParam() + 200, {.num_bodies = 6, .chain = true}), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Seeds, FloatingAbaOnTrees, ::testing::Range(1, 6));

TEST(FloatingAba, TheExampleRobots) {
  for (const test::FloatingExample* example : {&test::kAnymalExample, &test::kRomeoExample}) {
    SCOPED_TRACE(example->path);
    expectAbaEqualsTheMassMatrixSolve(test::loadExample(*example), 3);
  }
}

TEST(FloatingAba, RunsOnJets) {
  using Jet = ceres::Jet<double, 2>;
  const FloatingModel model = test::randomFloating(4, {.num_bodies = 5, .drives = true});
  const FloatingModelTpl<Jet> jet_model = model.cast<Jet>();
  FloatingDataTpl<Jet> jet_data(jet_model);
  FloatingData data(model);
  std::mt19937_64 rng(4);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 1.0);
  const Eigen::VectorXd tau = test::randomVector(rng, n, 5.0);
  BaseMotion base;
  base.twist = test::randomVector(rng, 6, 1.0);
  BaseMotionTpl<Jet> jet_base;
  for (int k = 0; k < 6; ++k) jet_base.twist[k] = Jet(base.twist[k]);
  VectorX<Jet> jq(n), jdq(n), jtau(n);
  for (int i = 0; i < n; ++i) jq[i] = Jet(q[i]), jdq[i] = Jet(dq[i]), jtau[i] = Jet(tau[i]);
  jq[0].v[0] = 1.0;    // d/dq_0
  jtau[0].v[1] = 1.0;  // d/dtau_0
  const VectorX<Jet> jacc =
      floatingAba(jet_model, jet_data, jet_base, jq, jdq, jtau, Vector6<Jet>::Zero());
  const Eigen::VectorXd acc = floatingAba(model, data, base, q, dq, tau, Vector6<double>::Zero());
  // The derivative along tau_0 is M^-1 e_6 (M times it is e_6); along q_0, central differences.
  const Eigen::MatrixXd M = floatingCrba(model, data, q);
  Eigen::VectorXd along_tau(6 + n);
  for (int r = 0; r < 6 + n; ++r) {
    EXPECT_NEAR(jacc[r].a, acc[r], 1e-12 * std::max(1.0, std::abs(acc[r])));
    along_tau[r] = jacc[r].v[1];
  }
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(6 + n);
  unit[6] = 1.0;
  // M's conditioning on the light distal bodies: 1e-10, as kAbaTolerance.
  EXPECT_LT((M * along_tau - unit).norm(), 1e-10);
  const double h = 1e-6;
  Eigen::VectorXd qp = q, qm = q;
  qp[0] += h, qm[0] -= h;
  const Eigen::VectorXd up = floatingAba(model, data, base, qp, dq, tau, Vector6<double>::Zero());
  const Eigen::VectorXd down = floatingAba(model, data, base, qm, dq, tau, Vector6<double>::Zero());
  for (int r = 0; r < 6 + n; ++r) {
    const double fd = (up[r] - down[r]) / (2 * h);
    // Central differences at h = 1e-6: truncation ~h^2 and round-off ~1e-16/h of the scale.
    EXPECT_NEAR(jacc[r].v[0], fd, 1e-6 * std::max(1.0, std::abs(fd)));
  }
}

}  // namespace
}  // namespace dynid
