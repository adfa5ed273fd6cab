#include "identifiability/base_parameters.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/puma560.hpp"
#include "identifiability/observation.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

BaseParameters structural(const Model& model, int samples = 150, std::uint64_t seed = 1) {
  const ParameterLayout layout = model.parameterLayout();
  return computeBaseParameters(observationFromRandomStates(model, samples, seed).W,
                               standardParameterNames(layout), 0.0,
                               defaultPreference(layout.num_links, layout.perLink()));
}

std::vector<std::string> expressions(const BaseParameters& base) {
  std::vector<std::string> out;
  for (int j = 0; j < base.numBase(); ++j) out.push_back(base.expression(j));
  return out;
}

TEST(BaseParameters, PlanarTwoLinkMatchesTheTextbook) {
  // Gravity in the plane: mx1 + l1 m2, my1, Izz1 + l1^2 m2, mx2, my2, Izz2 (l1 = 0.7).
  test::Planar2R arm;
  const BaseParameters with_gravity = structural(arm.model());
  EXPECT_EQ(
      expressions(with_gravity),
      (std::vector<std::string>{"mx1 + 0.7*m2", "my1", "Izz1 + 0.49*m2", "mx2", "my2", "Izz2"}));
  EXPECT_GT(with_gravity.rankGap(), 1e10);
  // Without gravity the first moments of link 1 no longer act: 4 base parameters.
  arm.g = 0.0;
  const BaseParameters no_gravity = structural(arm.model());
  EXPECT_EQ(expressions(no_gravity),
            (std::vector<std::string>{"Izz1 + 0.49*m2", "mx2", "my2", "Izz2"}));
  EXPECT_EQ(no_gravity.baseName(0), "Izz1R");
  EXPECT_EQ(no_gravity.baseName(1), "mx2");
}

TEST(BaseParameters, BaseRegressorReproducesTheFullOneForAnyTheta) {
  std::mt19937_64 rng(5);
  for (int seed = 0; seed < 4; ++seed) {
    const Model model = seed == 0 ? makePuma560(true) : test::randomTree(seed, {.drives = true});
    const BaseParameters base = structural(model);
    // A fresh observation (other states than the ones the base was computed from).
    const Observation check = observationFromRandomStates(model, 50, 99);
    const Eigen::MatrixXd W1 = base.baseRegressor(check.W);
    for (int trial = 0; trial < 3; ++trial) {
      const Eigen::VectorXd theta = test::randomVector(rng, base.numStandard(), 1.0);
      const Eigen::VectorXd full = check.W * theta;
      // Round-off of K's least-squares fit, relative to the torque scale.
      EXPECT_LT((W1 * base.project(theta) - full).norm(), 1e-9 * (1 + full.norm())) << seed;
    }
    // The null space is annihilated by W, and standardFromBase keeps beta.
    EXPECT_LT((check.W * base.nullSpace()).cwiseAbs().maxCoeff(),
              1e-8 * check.W.cwiseAbs().maxCoeff());
    const Eigen::VectorXd beta = test::randomVector(rng, base.numBase(), 1.0);
    const Eigen::VectorXd prior = test::randomVector(rng, base.numStandard(), 1.0);
    const Eigen::VectorXd theta = base.standardFromBase(beta, prior);
    EXPECT_LT((base.project(theta) - beta).norm(), 1e-12 * (1 + beta.norm()));
    for (int k : base.dependent) EXPECT_EQ(theta[k], prior[k]);
  }
}

TEST(BaseParameters, PumaStructuralCounts) {
  // Rigid: the PUMA's 36 base parameters; link 1's 9 parameters other than its inertia about the
  // joint-1 axis never act. With drives: + Ia3..Ia6 (Ia1 and Ia2 regroup with the inertias about
  // their axes) + 18 friction parameters = 58.
  const BaseParameters rigid = structural(makePuma560(false));
  EXPECT_EQ(rigid.numBase(), 36);
  EXPECT_EQ(rigid.zero_columns.size(), 9u);
  EXPECT_GT(rigid.rankGap(), 1e8);
  const BaseParameters driven = structural(makePuma560(true));
  EXPECT_EQ(driven.numBase(), 58);
  const std::vector<std::string> exprs = expressions(driven);
  EXPECT_NE(std::find(exprs.begin(), exprs.end(), "Ixx6 - Iyy6"), exprs.end());
  EXPECT_NE(std::find(exprs.begin(), exprs.end(), "Ia3"), exprs.end());
  EXPECT_EQ(std::find(exprs.begin(), exprs.end(), "Ia2"), exprs.end());
  // The same structure from another seed.
  EXPECT_EQ(structural(makePuma560(true), 150, 7).independent, driven.independent);
}

TEST(BaseParameters, ExcitationFindsAnUnmovedJoint) {
  const Model model = test::Planar2R().model();
  const BaseParameters base = structural(model);
  // The shoulder locked at q1 = 0: the Izz1R column (ddq1) vanishes and so does my1's gravity
  // column (g sin q1).
  Trajectory t;
  t.resize(2, 40);
  std::mt19937_64 rng(1);
  for (int k = 0; k < 40; ++k) {
    t.time[k] = k;
    t.q(1, k) = test::randomVector(rng, 1, 3.0)[0];
    t.dq(1, k) = test::randomVector(rng, 1, 2.0)[0];
    t.ddq(1, k) = test::randomVector(rng, 1, 2.0)[0];
  }
  const Observation o = observationFromTrajectory(model, t);
  const Excitation e = measureExcitation(base.baseRegressor(o.W));
  EXPECT_EQ(e.rank, base.numBase() - 2);
  ASSERT_EQ(e.unexcited.size(), 2u);
  EXPECT_EQ(base.baseName(e.unexcited[0]), "my1");
  EXPECT_EQ(base.baseName(e.unexcited[1]), "Izz1R");
}

TEST(BaseParameters, RejectsBadInput) {
  EXPECT_THROW(computeBaseParameters(Eigen::MatrixXd::Ones(5, 3), {"a", "b"}), InputError);
  Eigen::MatrixXd W = Eigen::MatrixXd::Ones(5, 2);
  W(1, 1) = std::nan("");
  EXPECT_THROW(computeBaseParameters(W, {"a", "b"}), InputError);
  EXPECT_THROW(computeBaseParameters(Eigen::MatrixXd::Ones(5, 2), {"a", "b"}, 0.0, {0, 0}),
               InputError);
}

}  // namespace
}  // namespace dynid
