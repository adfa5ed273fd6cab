// The floating-base regressor: Y theta is the floating RNEA for any theta, and its joint rows are
// the virtual chain's fixed-base regressor (tests/common/floating_models).
#include <gtest/gtest.h>

#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/regressor.hpp"
#include "tests/common/floating_models.hpp"

namespace dynid {
namespace {

class FloatingRegressorOnTrees : public ::testing::TestWithParam<int> {};

TEST_P(FloatingRegressorOnTrees, TimesAnyParametersIsTheInverseDynamics) {
  FloatingModel model = test::randomFloating(GetParam(), {.num_bodies = 7, .drives = true});
  std::mt19937_64 rng(GetParam() + 3);
  const int n = model.numJoints();
  for (int trial = 0; trial < 10; ++trial) {
    // Any theta, consistent or not: the regressor is linear in all of them.
    if (trial > 0)
      model.setStandardParameters(model.standardParameters() +
                                  test::randomVector(rng, model.numParameters(), 0.05)
                                      .cwiseProduct(model.standardParameters().cwiseAbs() +
                                                    Eigen::VectorXd::Ones(model.numParameters())));
    FloatingData data(model);
    BaseMotion base;
    base.rotation = rotationFromRpy(0.2 * trial, 0.5, -0.4);
    base.twist = test::randomVector(rng, 6, 1.0);
    base.acceleration = test::randomVector(rng, 6, 2.0);
    const Eigen::VectorXd q = test::randomVector(rng, n, 2.0), dq = test::randomVector(rng, n, 1.5);
    const Eigen::VectorXd ddq = test::randomVector(rng, n, 2.0);
    const Eigen::MatrixXd Y = floatingRegressor(model, data, base, q, dq, ddq);
    const Eigen::VectorXd tau = floatingRnea(model, data, base, q, dq, ddq);
    // Round-off of sums over ~10 n products on torques of order 10-100: 1e-12 relative.
    EXPECT_LT((Y * model.standardParameters() - tau).norm(), 1e-12 * std::max(1.0, tau.norm()));
    // The drives act between links, never on the base.
    const ParameterLayout layout = model.limbs().parameterLayout();
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < kDriveTermCount; ++k) {
        if (!layout.drives.has(k)) continue;
        EXPECT_EQ(Y.col(FloatingModel::limbColumn(layout.driveIndex(i, k))).head<6>().norm(), 0.0);
      }
  }
}

/// Over `trials` random states: Y's joint rows are the virtual chain's fixed-base regressor, and
/// Y theta the floating inverse dynamics.
void expectTheChainsRows(const FloatingModel& model, std::uint64_t seed, int trials) {
  const Model chain = test::virtualChain(model);
  FloatingData data(model);
  Data chain_data(chain);
  std::mt19937_64 rng(seed);
  const int n = model.numJoints();
  for (int trial = 0; trial < trials; ++trial) {
    const test::FloatingSample s = test::randomFloatingSample(model, chain, rng);
    const Eigen::MatrixXd Y = floatingRegressor(model, data, s.base, s.q, s.dq, s.ddq);
    const Eigen::MatrixXd Yc =
        jointTorqueRegressor(chain, chain_data, s.chain_q, s.chain_dq, s.chain_ddq);
    // Chain columns: the virtual bodies' 50, then the base body (chain body 5), then the limbs.
    const Eigen::MatrixXd joints = Yc.bottomRows(n).rightCols(10 * (n + 1));
    EXPECT_LT((Y.bottomRows(n) - joints).norm(), 1e-12 * std::max(1.0, joints.norm()));
    const Eigen::VectorXd tau = floatingRnea(model, data, s.base, s.q, s.dq, s.ddq);
    EXPECT_LT((Y * model.standardParameters() - tau).norm(), 1e-12 * std::max(1.0, tau.norm()));
  }
}

TEST_P(FloatingRegressorOnTrees, JointRowsAreTheVirtualChainsRegressor) {
  expectTheChainsRows(test::randomFloating(GetParam(), {.num_bodies = 8}), GetParam() + 11, 10);
}

INSTANTIATE_TEST_SUITE_P(Seeds, FloatingRegressorOnTrees, ::testing::Values(1, 2, 3));

/// The example robots (half of ANYmal C's joints about -e_x, on the unit axis' fast path).
TEST(FloatingRegressor, OnTheExampleRobotsIsTheChainsAndTheInverseDynamics) {
  for (const test::FloatingExample* example : {&test::kAnymalExample, &test::kRomeoExample})
    expectTheChainsRows(test::loadExample(*example), 5, 5);
}

}  // namespace
}  // namespace dynid
