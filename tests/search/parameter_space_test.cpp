#include "search/parameter_space.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(ParameterSpace, PaperFormBoundsAndFixedZeros) {
  const Model puma = makePuma560();
  const ParameterSpace space(puma, {});
  // Link 1: only Iyy (0.35) is non-zero; link 4: m, cy, Ixx, Iyy, Izz; link 5: m and three
  // inertias; link 6: m, cz and three inertias; links 2 and 3: all 7.
  EXPECT_EQ(space.numFree(), 1 + 7 + 7 + 5 + 4 + 5);
  EXPECT_EQ(space.freeNames().front(), "Iyy1");
  for (int p = 0; p < space.numFree(); ++p) {
    const double x0 = space.initial()[p];
    EXPECT_NEAR(space.upper()[p] - x0, 0.5 * std::abs(x0), 1e-15);
  }
  // The initial model is reproduced exactly by its own free vector.
  EXPECT_LT((space.standardAt(space.initial()) - puma.standardParameters()).cwiseAbs().maxCoeff(),
            1e-15);
  const ParameterSpace wide(puma, {.absolute_range = 0.1});
  EXPECT_EQ(wide.numFree(), 42);
  EXPECT_GE(wide.lower()[0], 0.0);  // m1 ranges over [0, 0.1], not below 0
}

TEST(ParameterSpace, ProjectionMeetsBoundsAndTotalMass) {
  const Model puma = makePuma560();
  const ParameterSpace space(perturbedModel(puma, 0.3, 1),
                             {.total_mass_constraint = true, .total_mass = 23.45});
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = space.initial() + test::randomVector(rng, space.numFree(), 1.0);
    const Eigen::VectorXd y = space.project(x);
    EXPECT_TRUE(space.feasible(y)) << trial;
    EXPECT_NEAR(space.totalMass(y), 23.45, 1e-10);
  }
  EXPECT_THROW(ParameterSpace(puma, {.total_mass_constraint = true, .total_mass = 100.0}),
               InputError);
}

TEST(ParameterSpace, StandardFormAndParameterError) {
  const Model tree = test::randomTree(4);
  const ParameterSpace space(tree, {.form = ParameterForm::kStandard});
  EXPECT_EQ(space.numFull(), 70);
  const Eigen::VectorXd truth = space.fullVector(tree);
  EXPECT_EQ(space.parameterError(space.initial(), truth), 0.0);
  // One parameter 10 % off: error 0.01 (eq. 1).
  Eigen::VectorXd x = space.initial();
  x[3] *= 1.1;
  EXPECT_NEAR(space.parameterError(x, truth), 0.01, 1e-12);
  EXPECT_THROW(parseParameterForm("dh"), InputError);
}

TEST(ParameterSpace, FixedMaskHoldsNamedParameters) {
  const Model puma = makePuma560();
  const ParameterSpace all(puma, {});
  const ParameterSpace masked(puma, {.fixed = {"m2", "cx3", "Iyy1"}});
  EXPECT_EQ(masked.numFree(), all.numFree() - 3);
  for (const std::string& name : masked.freeNames()) {
    EXPECT_NE(name, "m2");
    EXPECT_NE(name, "Iyy1");
  }
  // The held mass still counts towards the total.
  const ParameterSpace constrained(
      puma, {.fixed = {"m2"}, .total_mass_constraint = true, .total_mass = 23.45});
  EXPECT_NEAR(constrained.totalMass(constrained.initial()), 23.45, 1e-12);
  EXPECT_EQ(masked.modelAt(masked.initial()).inertias()[1].mass, 17.4);
  try {
    ParameterSpace(puma, {.fixed = {"mass2"}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot fix 'mass2'"), std::string::npos);
  }
}

}  // namespace
}  // namespace dynid
