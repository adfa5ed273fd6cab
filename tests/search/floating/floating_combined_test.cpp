// The combined estimator's GC term on a floating base (search/floating/floating_combined.hpp):
// its error is floatingGcError's, its Jacobian the residuals' derivative, the same for any thread
// count, and refineCombinedTerms with it turns a wrong trunk back into the robot's.
#include "search/floating/floating_combined.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "tests/common/floating_gc_data.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

FloatingGcOptions shortSegments() {
  FloatingGcOptions o;
  o.horizon = 0.02;
  o.num_segments = 6;
  return o;
}

/// The model's parameters with the trunk 10 % heavier (its shape the same).
Eigen::VectorXd heavierTrunk(const FloatingModel& model) {
  Eigen::VectorXd theta = model.standardParameters();
  theta.head<10>() *= 1.1;
  return theta;
}

struct Suspended : ::testing::Test {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingGcData data = test::suspended(model, 1000.0, 0.2);
  const int p = model.numParameters();
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(p, p);
};

TEST_F(Suspended, TheTermsErrorIsTheGcError) {
  const GcTerm term = floatingGcTerm(model, data, shortSegments(), identity, 2);
  const Eigen::VectorXd theta = heavierTrunk(model);
  FloatingModel heavier = model;
  heavier.setStandardParameters(theta);
  const double expected = floatingGcError(heavier, data, shortSegments()).error;
  // The same rollouts, segment by segment, summed in the same order.
  EXPECT_EQ(term.error(theta, {}), expected);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(term.linearise(theta, {}, &r, &J));
  EXPECT_EQ(r.size(), 6 * (2 * model.numJoints() + 9));
  // |r|^2 is the GC error up to the sum's order (a rotation vector's norm is the angle).
  EXPECT_NEAR(r.squaredNorm(), expected, 1e-12 * expected);
}

TEST_F(Suspended, ItsJacobianIsTheResidualsDerivative) {
  const GcTerm term = floatingGcTerm(model, data, shortSegments(), identity, 2);
  const Eigen::VectorXd theta = heavierTrunk(model);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(term.linearise(theta, {}, &r, &J));
  ASSERT_EQ(J.cols(), p);
  // Along random directions, central differences of the residuals (a step of 1e-5 of theta's
  // scale: truncation about 1e-10 relative) against J d: the forward differences J is made of
  // err by about their step, 1e-6 of each parameter, relative.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  FloatingModel m = model;
  const auto residuals = [&](const Eigen::VectorXd& t) {
    m.setStandardParameters(t);
    const FloatingGcResult s = floatingGcSegments(m, data, shortSegments());
    const Eigen::MatrixXd c = floatingGcResiduals(m, data, s, 1);
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(c.data(), c.size()));
  };
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd d(p);
    for (int i = 0; i < p; ++i) d[i] = normal(rng) * std::max(std::abs(theta[i]), 1e-3);
    const double h = 1e-5;
    const Eigen::VectorXd central = (residuals(theta + h * d) - residuals(theta - h * d)) / (2 * h);
    EXPECT_LT((J * d - central).norm(), 1e-4 * central.norm())
        << (J * d - central).norm() << " of " << central.norm();
  }
}

TEST_F(Suspended, TheSameForAnyThreadCount) {
  const Eigen::VectorXd theta = heavierTrunk(model);
  Eigen::VectorXd r1, r3;
  Eigen::MatrixXd J1, J3;
  ASSERT_TRUE(
      floatingGcTerm(model, data, shortSegments(), identity, 1).linearise(theta, {}, &r1, &J1));
  ASSERT_TRUE(
      floatingGcTerm(model, data, shortSegments(), identity, 3).linearise(theta, {}, &r3, &J3));
  EXPECT_EQ((r1 - r3).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((J1 - J3).cwiseAbs().maxCoeff(), 0.0);
}

TEST_F(Suspended, ACombinedEstimateTurnsAWrongTrunkBackIntoTheRobots) {
  const GcTerm term = floatingGcTerm(model, data, shortSegments(), identity, 2);
  const Eigen::VectorXd start = heavierTrunk(model), truth = model.standardParameters();
  // A torque term that knows nothing: a faint pull towards the start, so that the directions no
  // rollout sees stay where they are (its Hessian keeps every step defined).
  TorqueTerm weak;
  weak.cost = [&](const Eigen::VectorXd& t) { return 0.5e-8 * (t - start).squaredNorm(); };
  weak.derivatives = [&](const Eigen::VectorXd& t, Eigen::VectorXd* g, Eigen::MatrixXd* h) {
    *g = 1e-8 * (t - start);
    *h = 1e-8 * Eigen::MatrixXd::Identity(t.size(), t.size());
  };
  weak.scale = 1.0;
  CombinedOptions options;
  options.noise_floor = false;  // noise-free: the floor is the inputs' hold, below the start's
  options.max_iterations = 20;
  options.max_seconds = 0.0;
  const CombinedResult out = refineCombinedTerms(weak, term, start, options);
  EXPECT_TRUE(out.moved) << out.termination;
  // The sensor carries the true weight: the heavier trunk sinks (measured GC 100s of times the
  // truth's); the estimate rolls out as the robot does, within twice its hold error.
  const double robot = term.error(truth, {});
  EXPECT_LT(out.final_gc, 2.0 * robot) << out.final_gc << " against the robot's " << robot;
  EXPECT_GT(out.initial_gc, 50.0 * robot) << out.initial_gc;
  // The robot's whole mass, which its weight on the sensor shows, back within 0.1 % of the
  // robot's (it started 5 % off; measured 0.02 %). How that mass is split among the links the
  // suspended motion barely shows: the faint pull decides it, and the trunk keeps most of its
  // excess.
  ASSERT_EQ(p, kLinkParameterCount * (model.numJoints() + 1));  // no drive terms
  double mass = 0.0, robot_mass = 0.0;
  for (int body = 0; body < model.numJoints() + 1; ++body) {
    mass += out.theta[kLinkParameterCount * body];
    robot_mass += truth[kLinkParameterCount * body];
  }
  EXPECT_NEAR(mass, robot_mass, 1e-3 * robot_mass) << mass << " against " << robot_mass;
}

TEST_F(Suspended, RefusesAProjectionOfAnotherSize) {
  EXPECT_THROW(floatingGcTerm(model, data, shortSegments(), Eigen::MatrixXd::Identity(3, 3)),
               InputError);
}

}  // namespace
}  // namespace dynid
