#include "core/momentum.hpp"

#include <gtest/gtest.h>

#include "core/crba.hpp"
#include "core/energy.hpp"
#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

class Momentum : public ::testing::TestWithParam<bool> {};  // with drive terms or without

/// max |d/dt (M dq) - (tau - beta)| at a random state of `model` (scales 1.5, 2, 3 for q, dq,
/// ddq times `scale`), the rate by central differences along (dq, ddq); and |tau| there.
std::pair<double, double> rateError(const Model& model, std::uint64_t seed, double scale) {
  Data data(model);
  std::mt19937_64 rng(seed);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.5 * scale),
                        dq = test::randomVector(rng, n, 2 * scale),
                        ddq = test::randomVector(rng, n, 3 * scale);
  Eigen::VectorXd p, beta, p_plus, p_minus, unused;
  momentumTerms(model, data, q, dq, p, beta);
  const Eigen::VectorXd tau = rnea(model, data, q, dq, ddq);
  const double h = 1e-5;
  momentumTerms(model, data, Eigen::VectorXd(q + h * dq), Eigen::VectorXd(dq + h * ddq), p_plus,
                unused);
  momentumTerms(model, data, Eigen::VectorXd(q - h * dq), Eigen::VectorXd(dq - h * ddq), p_minus,
                unused);
  const Eigen::VectorXd rate = (p_plus - p_minus) / (2 * h);
  return {(rate - (tau - beta)).cwiseAbs().maxCoeff(), tau.norm()};
}

TEST_P(Momentum, IsTheMassMatrixTimesTheVelocity) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Model model = test::randomTree(seed, {.drives = GetParam()});
    Data data(model);
    std::mt19937_64 rng(seed);
    const int n = model.numJoints();
    const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), dq = test::randomVector(rng, n, 2);
    Eigen::VectorXd p, beta;
    momentumTerms(model, data, q, dq, p, beta);
    const Eigen::VectorXd expected = crba(model, data, q) * dq;
    // Two orderings of the same sums of ~50 products of O(1) terms: round-off only.
    EXPECT_LT((p - expected).cwiseAbs().maxCoeff(), 1e-12 * (1 + expected.norm())) << seed;
  }
}

// The observer's law: d/dt (M dq) = tau - beta along any motion, tau = rnea(q, dq, ddq).
TEST_P(Momentum, ItsRateIsTheTorqueLessTheBias) {
  for (std::uint64_t seed : {4u, 5u, 6u}) {
    const auto [error, torque] =
        rateError(test::randomTree(seed, {.drives = GetParam()}), seed, 1.0);
    // Central difference of a smooth path: truncation O(h^2 |d3p/dt3|) ~ 1e-10 * 1e2, cancellation
    // ~ 1e-16 * 10 / 1e-5 ~ 1e-10; torques are O(10..100) N m.
    EXPECT_LT(error, 1e-6 * (1 + torque)) << seed;
  }
}

// C^T dq is the gradient of the kinetic energy: beta = g + tau_f - dT/dq.
TEST_P(Momentum, TheBiasHoldsTheKineticEnergysGradient) {
  const Model model = test::randomTree(7, {.drives = GetParam()});
  Data data(model);
  std::mt19937_64 rng(7);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), dq = test::randomVector(rng, n, 2);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd p, beta;
  momentumTerms(model, data, q, dq, p, beta);
  // Gravity from the model without drives at rest; friction as the drives' share at speed dq.
  Model no_drives = model;
  no_drives.setDriveTerms(DriveTerms::none());
  Data plain(no_drives);
  const Eigen::VectorXd gravity = rnea(no_drives, plain, q, zero, zero);
  const Eigen::VectorXd friction =
      rnea(model, data, q, dq, zero) - rnea(no_drives, plain, q, dq, zero);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd qp = q, qm = q;
    qp[k] += h, qm[k] -= h;
    const double gradient =
        (kineticEnergy(model, data, qp, dq) - kineticEnergy(model, data, qm, dq)) / (2 * h);
    // Central difference: truncation ~1e-12, cancellation 1e-16 * 100 J / 1e-6 ~ 1e-8.
    EXPECT_NEAR(beta[k], gravity[k] + friction[k] - gradient, 1e-6) << "joint " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Drives, Momentum, ::testing::Bool());

// The same law on the built-in arms (modified-DH Panda, standard-DH PUMA with its drives).
TEST(Momentum, ItsRateIsTheTorqueLessTheBiasOnTheBuiltInArms) {
  for (const Model& model : {makePanda(true), makePuma560(true)}) {
    const auto [error, torque] = rateError(model, 9, 0.5);
    // As above: central differences, 1e-6 of the torques' size.
    EXPECT_LT(error, 1e-6 * (1 + torque)) << model.name;
  }
}

TEST(Momentum, RefusesVectorsOfAnotherSize) {
  const Model model = test::randomTree(1);
  Data data(model);
  Eigen::VectorXd p, beta;
  EXPECT_THROW(momentumTerms(model, data, Eigen::VectorXd::Zero(3),
                             Eigen::VectorXd::Zero(model.numJoints()), p, beta),
               InputError);
}

}  // namespace
}  // namespace dynid
