#include "core/integrators.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/energy.hpp"
#include "core/errors.hpp"
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
