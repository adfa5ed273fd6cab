#include "analysis/studies/comparison.hpp"

#include <gtest/gtest.h>

#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "identifiability/observation.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Comparison, TheTruthScoresZeroAndAPerturbedModelDoesNot) {
  const Model truth = makePuma560();
  const Trajectory data = test::pumaSinusoidTrajectory(truth, 1.0, 0.5, 0.2, 0.6);
  const GcProblem problem = makeGcProblem(data, {.num_segments = 5});
  const ParameterSpace space(perturbedModel(truth, 0.2, 3), {});
  const ParameterLayout layout = truth.parameterLayout();
  const BaseParameters base = computeBaseParameters(
      observationFromRandomStates(truth, 200, 1).W, standardParameterNames(layout), 0.0,
      defaultPreference(layout.num_links, layout.perLink()));
  ThreadPool pool(1);
  Comparison comparison(truth, space, base, problem, problem, data, pool);
  const MethodMetrics exact = comparison.measure("truth", truth, 1.0, 3, 0.5);
  // Noise-free data from the same integrator: the truth's rollouts repeat the simulation up to
  // round-off (the GC error's lanes sum short dot products in another order than the simulation's
  // scalar steps: state differences below 1e-13, so squared sums below 1e-24), and its torques
  // match to round-off (1e-12 N m allows for RNEA's summation order).
  EXPECT_LT(exact.gc_error_train, 1e-24);
  EXPECT_LT(exact.gc_error_test, 1e-24);
  EXPECT_LT(exact.torque_rms_test, 1e-12);
  EXPECT_EQ(exact.param_error, 0.0);
  EXPECT_EQ(exact.base_param_error, 0.0);
  EXPECT_EQ(exact.key, "truth");
  EXPECT_EQ(exact.evaluations, 3);
  const Model guess = perturbedModel(truth, 0.2, 3);
  const MethodMetrics off = comparison.measure("guess", guess, 1.0, 0, 0.0);
  EXPECT_GT(off.gc_error_train, 0.0);
  EXPECT_GT(off.torque_rms_test, 1e-3);
  EXPECT_GT(off.param_error, 1e-3);
  EXPECT_GT(off.base_param_error, 1e-3);
  EXPECT_EQ(off.gc_error_train, comparison.trainGc(guess));
}

}  // namespace
}  // namespace dynid
