#include "core/integrators.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/aba.hpp"
#include "core/energy.hpp"
#include "core/errors.hpp"
#include "core/integrators-inl.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

double totalEnergy(const Model& model, Data& data, const Eigen::VectorXd& q,
                   const Eigen::VectorXd& dq) {
  return kineticEnergy(model, data, q, dq) + potentialEnergy(model, data, q);
}

TEST(Integrators, Rk4ConservesEnergyWithoutTorqueOrFriction) {
  // RK4, 1 ms, 2 s, zero torque: the PUMA falls and swings under gravity alone.
  for (int seed = 0; seed < 3; ++seed) {
    const Model model =
        seed == 0 ? makePuma560(false) : test::randomTree(seed, {.prismatic = false});
    Data data(model);
    const int n = model.numJoints();
    std::mt19937_64 rng(seed);
    Eigen::VectorXd q = test::randomVector(rng, n, 1.0), dq = test::randomVector(rng, n, 1.0);
    const Eigen::VectorXd tau = Eigen::VectorXd::Zero(n);
    const double e0 = totalEnergy(model, data, q, dq);
    double scale = 0.0;  // the largest kinetic energy reached: the scale of the exchange
    for (int k = 0; k < 2000; ++k) {
      rk4Step(model, data, q, dq, tau, 1e-3);
      scale = std::max(scale, kineticEnergy(model, data, q, dq));
    }
    const double drift = std::abs(totalEnergy(model, data, q, dq) - e0);
    // RK4's local error O(h^5) over 2000 steps; measured drift is about 1e-9 of the energy
    // exchanged, so 1e-6 leaves margin without hiding a first-order (Euler-like) error, whose
    // drift here is 1e-3 or more.
    EXPECT_LT(drift, 1e-6 * scale) << "seed " << seed << ", drift " << drift << " J of " << scale;
  }
}

/// Error at t = 0.2 s against a reference computed with step h/16. Rigid body only: Coulomb
/// friction's sign(dq) is discontinuous and would spoil any integrator's order.
double errorWithStep(IntegratorType type, double h) {
  const Model model = makePuma560(false);
  Data data(model);
  Eigen::VectorXd tau(6);
  tau << 5, -30, 10, 0.1, -0.2, 0.05;
  auto run = [&](double step) {
    Eigen::VectorXd q = Eigen::VectorXd::Constant(6, 0.2), dq = Eigen::VectorXd::Constant(6, 0.5);
    const int steps = static_cast<int>(std::lround(0.2 / step));
    for (int k = 0; k < steps; ++k) integratorStep(type, model, data, q, dq, tau, step);
    Eigen::VectorXd x(12);
    x << q, dq;
    return x;
  };
  return (run(h) - run(h / 16)).norm();
}

// RK4's stages 2-4 form their joint transforms from the step's sin q and cos q by angle addition
// (a series for the small stage offset, sin/cos calls beyond 1e-2 rad); the step must equal the
// textbook one built from four plain forward-dynamics calls. Trees with prismatic and
// arbitrary-axis joints; slow states (series) and fast ones with a long step (the sin/cos
// fallback).
TEST(Integrators, Rk4StagesEqualTheTextbookStep) {
  for (int seed = 0; seed < 4; ++seed) {
    const Model model = seed == 0 ? makePuma560(true) : test::randomTree(seed);
    Data data(model), reference(model);
    const int n = model.numJoints();
    std::mt19937_64 rng(seed + 100);
    for (const auto& [speed, h] : {std::pair{1.0, 1e-3}, std::pair{50.0, 1e-2}}) {
      const Eigen::VectorXd q0 = test::randomVector(rng, n, 2.0);
      const Eigen::VectorXd dq0 = test::randomVector(rng, n, speed);
      const Eigen::VectorXd tau = test::randomVector(rng, n, 5.0);
      Eigen::VectorXd q = q0, dq = dq0;
      rk4Step(model, data, q, dq, tau, h);
      // k_i = (dq_i, ddq_i) at the stage states.
      const auto f = [&](const Eigen::VectorXd& qs, const Eigen::VectorXd& dqs) {
        return Eigen::VectorXd(aba(model, reference, qs, dqs, tau));
      };
      const Eigen::VectorXd a1 = f(q0, dq0);
      const Eigen::VectorXd v2 = dq0 + h / 2 * a1, a2 = f(q0 + h / 2 * dq0, v2);
      const Eigen::VectorXd v3 = dq0 + h / 2 * a2, a3 = f(q0 + h / 2 * v2, v3);
      const Eigen::VectorXd v4 = dq0 + h * a3, a4 = f(q0 + h * v3, v4);
      const Eigen::VectorXd q_ref = q0 + h / 6 * (dq0 + 2 * v2 + 2 * v3 + v4);
      const Eigen::VectorXd dq_ref = dq0 + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      // The series are off by under 2 % of an ulp: only round-off of sin/cos (1 ulp) and of the
      // recursion separates the two, 1e-12 of the state's scale far above it and below any
      // error in a stage's angle (h dq ~ 1e-3, so a wrong stage shows at 1e-6 or more).
      EXPECT_LT((q - q_ref).norm(), 1e-12 * (1.0 + q_ref.norm())) << "seed " << seed;
      EXPECT_LT((dq - dq_ref).norm(), 1e-12 * (1.0 + dq_ref.norm()))
          << "seed " << seed << ", speed " << speed;
    }
  }
}

// The stage transforms by angle addition equal the joint transforms at the stage angle, across
// the series' range (|d| <= 1e-2) and beyond it (sin/cos calls).
TEST(Integrators, StageTransformsEqualTheJointTransforms) {
  const Model model = test::randomTree(5);
  Data data(model);
  const int n = model.numJoints();
  std::mt19937_64 rng(7);
  const Eigen::VectorXd q = test::randomVector(rng, n, 3.0);
  for (int i = 0; i < n; ++i) data.sin_q[i] = std::sin(q[i]), data.cos_q[i] = std::cos(q[i]);
  for (const double d : {1e-9, -3e-6, 1e-3, -9.9e-3, 1e-2, 2e-2, -0.7}) {
    const Eigen::VectorXd q_stage = q + Eigen::VectorXd::Constant(n, d);
    integrators_detail::stageTransforms(model, data, q, q_stage);
    for (int i = 0; i < n; ++i) {
      const Pose<double> expected = jointTransform(model, i, q_stage[i]);
      // Entries of a rotation are at most 1: a few ulps of round-off; a wrong series term shows
      // at d^3 / 6 ~ 1e-7 for d near 1e-2.
      EXPECT_LT((data.liMi[i].rotation - expected.rotation).cwiseAbs().maxCoeff(), 1e-15)
          << "joint " << i << ", d " << d;
      EXPECT_LT((data.liMi[i].translation - expected.translation).cwiseAbs().maxCoeff(), 1e-15)
          << "joint " << i << ", d " << d;
    }
  }
}

TEST(Integrators, ConvergeAtTheirOrder) {
  // Halving the step divides the error by 2^order: 16 for RK4, 2 for semi-implicit Euler.
  const double rk4_ratio =
      errorWithStep(IntegratorType::kRk4, 4e-3) / errorWithStep(IntegratorType::kRk4, 2e-3);
  EXPECT_GT(rk4_ratio, 12.0);
  EXPECT_LT(rk4_ratio, 20.0);
  const double euler_ratio = errorWithStep(IntegratorType::kSemiImplicitEuler, 4e-3) /
                             errorWithStep(IntegratorType::kSemiImplicitEuler, 2e-3);
  EXPECT_GT(euler_ratio, 1.7);
  EXPECT_LT(euler_ratio, 2.5);
}

TEST(Integrators, ParsesNames) {
  EXPECT_EQ(parseIntegrator("rk4"), IntegratorType::kRk4);
  EXPECT_EQ(parseIntegrator("euler"), IntegratorType::kSemiImplicitEuler);
  EXPECT_STREQ(integratorName(IntegratorType::kRk4), "rk4");
  EXPECT_THROW(parseIntegrator("rk45"), InputError);
}

}  // namespace
}  // namespace dynid
