#include "analysis/estimation/pipeline.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// Noise-free PUMA data, its base parameters, observation and GC problem.
struct Fixture {
  Model truth = makePuma560(false);
  Trajectory data = test::pumaTrajectory(truth, 2.0, 0.0, 1);
  BaseParameters base = test::pumaBase(truth);
  Observation observation = observationFromTrajectory(truth, data);
  // Four segments of 20 ms: enough for every claim here, and the refinements (Jets through the
  // integrator) stay short under the sanitizers.
  GcProblem gc = makeGcProblem(data, SegmentOptions{.horizon = 0.02, .num_segments = 4});

  EstimationProblem problem(const Model& start) {
    EstimationProblem p;
    p.model = truth;
    p.base = &base;
    p.least_squares.observation = &observation;
    p.prior = start.standardParameters();
    p.train_gc = &gc;
    p.start = start;
    p.search_budget.max_evaluations = 60;  // deterministic for a seed, whatever the machine
    p.refine.options.max_iterations = 3;
    p.refine.options.function_tolerance = 1e-6;
    p.threads = 2;
    return p;
  }
};

TEST(Pipeline, LeastSquaresFromAStreamEqualTheDenseObservation) {
  Fixture s;
  LeastSquaresStream stream(s.base, s.truth);
  stream.addTrajectory(s.truth, s.data);
  const Eigen::VectorXd prior = s.truth.standardParameters();
  for (Method method : leastSquaresMethods()) {
    const LeastSquaresOutcome dense =
        leastSquaresEstimate(method, s.base, {&s.observation, nullptr, {}, {}}, prior);
    const LeastSquaresOutcome streamed = leastSquaresEstimate(
        method, s.base, {nullptr, &stream, s.truth.parameterLayout(), {}}, prior);
    // The same rows factored in another order: round-off at a condition number ~1e2.
    EXPECT_LT((dense.estimate.beta - streamed.estimate.beta).norm(),
              1e-9 * dense.estimate.beta.norm())
        << methodName(method);
    EXPECT_EQ(dense.pc.has_value(), method == Method::kPc);
  }
  EXPECT_THROW(leastSquaresEstimate(Method::kNlo, s.base, {&s.observation, nullptr, {}, {}}, prior),
               InputError);
  EXPECT_THROW(leastSquaresEstimate(Method::kOls, s.base, {}, prior), InputError);
}

TEST(Pipeline, RunnerMemoisesSearchesAndRefinesTheirResult) {
  Fixture s;
  const Model start = perturbedModel(s.truth, 0.3, 5);
  MethodRunner runner(s.problem(start));
  EXPECT_EQ(runner.searchResult(Method::kNlo), nullptr);
  const Estimate refined = runner.run(Method::kNloRefined);  // searches first
  const SearchResult* found = runner.searchResult(Method::kNlo);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->evaluations, 60);
  const Estimate searched = runner.run(Method::kNlo);  // the same search, not a second one
  EXPECT_EQ(runner.searchResult(Method::kNlo), found);
  EXPECT_EQ(searched.model.standardParameters(),
            runner.space(Method::kNlo).modelAt(found->best_x).standardParameters());
  // Refinement starts at the search's point and does not end above it (keep-if-better).
  GcWorkspace workspace(1);
  ThreadPool pool(1);
  EXPECT_LE(gcError(refined.model, s.gc, workspace, pool),
            gcError(searched.model, s.gc, workspace, pool));
  EXPECT_FALSE(std::isnan(refined.start_gc));
  EXPECT_TRUE(std::isnan(searched.start_gc));
  // NLO's space holds the start's total mass, GA's does not constrain it.
  EXPECT_NEAR(totalMass(searched.model), totalMass(start), 1e-9 * totalMass(start));
}

TEST(Pipeline, LeastSquaresUseThePriorAndThePriorWeight) {
  Fixture s;
  const Model start = perturbedModel(s.truth, 0.3, 6);
  EstimationProblem light = s.problem(start), heavy = s.problem(start);
  heavy.physical.prior_weight = 1e6;
  MethodRunner a(std::move(light)), b(std::move(heavy));
  const Estimate ols = a.run(Method::kOls);
  // What the data cannot see comes from the prior (the start), what they see from the data.
  EXPECT_LT(baseParameterError(s.base.project(ols.model.standardParameters()),
                               s.base.project(s.truth.standardParameters())),
            1e-8);
  ASSERT_NE(ols.least_squares, nullptr);
  EXPECT_EQ(ols.evaluations, 0);
  // A heavier prior pulls pc's estimate towards the (wrong) start: a worse fit to the data.
  const Estimate pc_light = a.run(Method::kPc), pc_heavy = b.run(Method::kPc);
  EXPECT_GT(pc_light.evaluations, 0);
  EXPECT_LT(pc_light.least_squares->estimate.relative_error,
            pc_heavy.least_squares->estimate.relative_error);
}

TEST(Pipeline, SearchesCanStartFromThePhysicallyConsistentEstimate) {
  Fixture s;
  EstimationProblem problem = s.problem(perturbedModel(s.truth, 0.3, 7));
  problem.search_start = SearchStart::kPhysicallyConsistent;
  MethodRunner runner(std::move(problem));
  const Estimate pc = runner.run(Method::kPc);
  EXPECT_EQ(runner.searchStart().standardParameters(), pc.model.standardParameters());
  EXPECT_EQ(runner.space(Method::kGa).initial(),
            runner.space(Method::kGa).freeOf(runner.space(Method::kGa).fullVector(pc.model)));
}

TEST(Pipeline, TheMassPlaneAndTheSpaceOptionsShapeEverySearchSpace) {
  Fixture s;
  const Model start = perturbedModel(s.truth, 0.3, 8);
  for (MassPlane plane : {MassPlane::kAuto, MassPlane::kOn, MassPlane::kOff}) {
    EstimationProblem problem = s.problem(start);
    problem.mass_plane = plane;
    problem.space.relative_range = 0.25;
    problem.total_mass = 1.1 * totalMass(start);  // inside the +-25 % bounds
    MethodRunner runner(std::move(problem));
    for (Method method : {Method::kNlo, Method::kGa, Method::kHybridRefined}) {
      const SpaceOptions& o = runner.space(method).options();
      const bool expected =
          plane == MassPlane::kOn || (plane == MassPlane::kAuto && searchOf(method) != Method::kGa);
      EXPECT_EQ(o.total_mass_constraint, expected) << methodName(method);
      EXPECT_EQ(o.total_mass, 1.1 * totalMass(start));
      EXPECT_EQ(o.relative_range, 0.25);
    }
    // One space per plane, shared by the methods on it.
    EXPECT_EQ(runner.sharedSpace(Method::kNlo) == runner.sharedSpace(Method::kGa),
              plane != MassPlane::kAuto);
  }
}

TEST(Pipeline, RefineFromIsTheRefinementOfAnyPointWithTheProblemsOptions) {
  Fixture s;
  const Model start = perturbedModel(s.truth, 0.3, 9);
  MethodRunner runner(s.problem(start));
  const ParameterSpace& space = runner.space(Method::kNlo);
  const Eigen::VectorXd x0 = space.project(space.initial());
  const RefineResult through_runner = runner.refineFrom(space, x0);
  RefineOptions options = s.problem(start).refine.options;
  options.num_threads = 2;
  const BaseCoordinates coordinates = s.base.coordinates();
  const RefineResult direct = refineGc(space, s.gc, x0, options, &coordinates);
  EXPECT_EQ(through_runner.x, direct.x);  // deterministic for any thread count
  EXPECT_EQ(through_runner.iterations, direct.iterations);
  EXPECT_LE(through_runner.final_gc, through_runner.initial_gc);
}

TEST(Pipeline, ProblemsWithoutTheirPartsAreRefused) {
  Fixture s;
  EstimationProblem no_base = s.problem(s.truth);
  no_base.base = nullptr;  // searches run without base parameters, least squares do not
  MethodRunner searcher(std::move(no_base));
  EXPECT_THROW(searcher.run(Method::kOls), InputError);
  EXPECT_NO_THROW(searcher.run(Method::kNlo));
  EstimationProblem no_gc = s.problem(s.truth);
  no_gc.train_gc = nullptr;
  MethodRunner runner(std::move(no_gc));
  EXPECT_NO_THROW(runner.run(Method::kWls));
  EXPECT_THROW(runner.run(Method::kGa), InputError);
  EstimationProblem bad_prior = s.problem(s.truth);
  bad_prior.prior = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(MethodRunner{std::move(bad_prior)}, InputError);
}

}  // namespace
}  // namespace dynid
