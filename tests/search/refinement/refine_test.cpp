// The refinement driver: from perturbed starts and starts at the bounds to the truth, estimated and
// chained starts, bounds, stops and bad input.
#include "search/refinement/refine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/observation.hpp"
#include "tests/common/gradient_check.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

BaseCoordinates pumaBase(const Model& model, std::vector<std::string>* names = nullptr) {
  const BaseCoordinates out = structuralBaseParameters(model, {.samples = 200}).coordinates();
  if (names != nullptr) *names = out.names;
  return out;
}

TEST(Refine, RecoversTheTruthFromAPerturbedStartOnNoiseFreeData) {
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.1, 7), {});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(4.0), {.num_segments = 20});
  std::vector<std::string> names;
  const BaseCoordinates base = pumaBase(truth, &names);
  const RefineResult result = refineGc(space, problem, space.initial(), {.num_threads = 2}, &base);
  EXPECT_TRUE(result.usable) << result.termination;
  EXPECT_LT(result.final_gc, 1e-8 * result.initial_gc) << result.termination;
  // Noise-free data determine every base parameter: the refined ones equal the truth's.
  const Eigen::VectorXd beta_true = base.projection * truth.standardParameters();
  double largest = 0.0;
  EXPECT_LT(baseParameterError(result.beta, beta_true, &largest), 1e-4);
  EXPECT_GT(result.gauge_dimension, 0);
  // ...while the paper parameters that the data cannot see stay where the search left them.
  const Eigen::VectorXd truth_full = space.fullVector(truth);
  EXPECT_GT(space.parameterError(result.x, truth_full), 1e-3);
  // Every direction the free parameters cannot move beta along is reported.
  EXPECT_EQ(static_cast<int>(result.free_directions.size()),
            space.numFree() - result.free_parameter_rank);
  EXPECT_FALSE(result.free_directions.empty());
  EXPECT_EQ(result.beta_covariance.rows(), static_cast<int>(names.size()));
  EXPECT_EQ(result.history.front().cost, result.initial_cost);
}
TEST(Refine, BaseStageReachesTheTruthFromAStartAtTheBounds) {
  const Model truth = makePuma560();
  const Model guess = perturbedModel(truth, 0.3, 13);
  const ParameterSpace space(
      guess, {.total_mass_constraint = true,
              .total_mass = truth.standardParameters()(Eigen::seqN(0, 6, 10)).sum()});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(2.0), {.num_segments = 10});
  const BaseCoordinates base = pumaBase(truth);
  // Every third free parameter at its lower bound, every third at its upper one.
  Eigen::VectorXd x0 = space.initial();
  for (int j = 0; j < space.numFree(); ++j)
    if (j % 3 != 2) x0[j] = j % 3 == 0 ? space.lower()[j] : space.upper()[j];
  x0 = space.project(x0);
  const RefineResult result = refineGc(space, problem, x0, {.num_threads = 2}, &base);
  EXPECT_TRUE(result.base_stage);
  EXPECT_TRUE(result.map_back_used);
  // The truth is inside the bounds and on the mass plane, so the map back is exact: 1e-13 measured,
  // 1e-9 allows for LM stopping at its tolerances on another platform, far below a wrong fit's.
  EXPECT_LT(result.map_back_error, 1e-9);
  EXPECT_LT(result.final_gc, 1e-8 * result.initial_gc) << result.termination;
  const Eigen::VectorXd beta_true = base.projection * truth.standardParameters();
  EXPECT_LT(baseParameterError(result.beta, beta_true), 1e-6);
  EXPECT_TRUE(space.feasible(result.x));
  EXPECT_EQ(result.history.front().stage, "base");
  EXPECT_EQ(result.history.back().stage, "parameters");
}
TEST(Refine, EstimatedStartsStayAtExactMeasurements) {
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.05, 9), {});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(2.0), {.num_segments = 10});
  // In base coordinates, as the pipeline refines whenever it has them: the start states meet their
  // measurements to 1e-15 within 3 s. In the rank-deficient free parameters alone the solver
  // crawls along the unidentifiable directions and needs all 200 iterations (38 s) to get the
  // states within 1e-7 (ChainedStartsStayAtExactMeasurements covers that path's solver choice).
  const BaseCoordinates base = pumaBase(truth);
  const RefineResult result = refineGc(space, problem, space.initial(),
                                       {.estimate_initial_states = true, .num_threads = 2}, &base);
  EXPECT_EQ(result.linear_solver, "SPARSE_SCHUR");
  EXPECT_LT(result.final_gc, 1e-8 * result.initial_gc) << result.termination;
  // Noise-free starts are exact: the estimated ones end where they were measured.
  for (int s = 0; s < problem.numSegments(); ++s) {
    Eigen::VectorXd measured(12);
    measured << problem.data.q.col(problem.starts[s]), problem.data.dq.col(problem.starts[s]);
    EXPECT_LT((result.initial_states.col(s) - measured).norm(), 1e-7) << "segment " << s;
  }
}
TEST(Refine, ChainedStartsStayAtExactMeasurements) {
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.05, 9), {});
  // 1 s in every non-overlapping 50 ms segment: 20 contiguous segments, 19 joins.
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 0});
  const BaseCoordinates base = pumaBase(truth);
  const RefineResult result = refineGc(space, problem, space.initial(),
                                       {.estimate_initial_states = true, .num_threads = 2}, &base);
  EXPECT_EQ(result.linear_solver, "SPARSE_NORMAL_CHOLESKY");
  EXPECT_EQ(result.chained_segments, problem.numSegments() - 1);
  EXPECT_LT(result.final_gc, 1e-8 * result.initial_gc) << result.termination;
  for (int s = 0; s < problem.numSegments(); ++s) {
    Eigen::VectorXd measured(12);
    measured << problem.data.q.col(problem.starts[s]), problem.data.dq.col(problem.starts[s]);
    EXPECT_LT((result.initial_states.col(s) - measured).norm(), 1e-7) << "segment " << s;
  }
  // Without the continuity weight the same segments stay independent.
  const RefineResult independent =
      refineGc(space, problem, space.initial(),
               {.estimate_initial_states = true, .continuity_weight = 0.0, .max_iterations = 1});
  EXPECT_EQ(independent.linear_solver, "SPARSE_SCHUR");
  EXPECT_EQ(independent.chained_segments, 0);
}
TEST(Refine, ChainedStartsRemoveStateNoise) {
  const Model truth = makePuma560();
  const Trajectory clean = test::pumaSearchTrajectory(1.0);
  Trajectory noisy = clean;
  std::mt19937_64 random(3);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (Eigen::Index k = 0; k < noisy.q.size(); ++k) {
    noisy.q.data()[k] += 1e-4 * gauss(random);
    noisy.dq.data()[k] += 1e-3 * gauss(random);
  }
  const GcProblem problem = makeGcProblem(noisy, {.num_segments = 0});
  // The mass of link 6 alone free, within 1e-9 of the truth: the states do the moving.
  std::vector<std::string> fixed;
  for (const std::string& name : paperParameterNames(6))
    if (name != "m6") fixed.push_back(name);
  const ParameterSpace space(truth, {.relative_range = 1e-9, .fixed = fixed});
  const auto stateError = [&](const Eigen::MatrixXd& starts) {
    double q = 0.0, dq = 0.0;
    for (int s = 0; s < problem.numSegments(); ++s) {
      const int k = problem.starts[s];
      q += (starts.col(s).head(6) - clean.q.col(k)).squaredNorm();
      dq += (starts.col(s).tail(6) - clean.dq.col(k)).squaredNorm();
    }
    return std::pair{std::sqrt(q / (6.0 * problem.numSegments())),
                     std::sqrt(dq / (6.0 * problem.numSegments()))};
  };
  // Stopped at a relative cost change of 1e-6 (46 iterations): the state errors below agree to 5
  // digits with those at the default 1e-16 (79 iterations, the last 40 lowering the cost by 7e-5 of
  // itself).
  const RefineResult chained =
      refineGc(space, problem, space.initial(),
               {.estimate_initial_states = true, .function_tolerance = 1e-6, .num_threads = 2});
  const RefineResult measured = refineGc(space, problem, space.initial(), {.max_iterations = 1});
  const auto [q_measured, dq_measured] = stateError(measured.initial_states);
  const auto [q_chained, dq_chained] = stateError(chained.initial_states);
  // The measurement noise itself, to sampling error over 120 values (about 10 %).
  EXPECT_NEAR(q_measured, 1e-4, 2e-5);
  EXPECT_NEAR(dq_measured, 1e-3, 2e-4);
  // Measured: velocity errors fall to 0.22x the noise, positions to 0.62x; the bounds 0.5x and
  // 0.9x sit far outside the ~10 % sampling error of 120 values.
  EXPECT_LT(dq_chained, 0.5 * dq_measured);
  EXPECT_LT(q_chained, 0.9 * q_measured);
}
TEST(Refine, FlagsBoundsAndStops) {
  const Model truth = makePuma560();
  // A 1 % range around a 10 % perturbation: the truth is out of reach and bounds become active.
  const ParameterSpace space(perturbedModel(truth, 0.1, 11), {.relative_range = 0.01});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 10});
  const RefineResult result = refineGc(space, problem, space.initial(), {.max_iterations = 20});
  EXPECT_FALSE(result.at_bound.empty());
  for (int j = 0; j < space.numFree(); ++j) {
    EXPECT_GE(result.x[j], space.lower()[j]);
    EXPECT_LE(result.x[j], space.upper()[j]);
  }
  std::atomic<bool> stop{true};
  RefineOptions stopping{.max_iterations = 20};
  stopping.control.stop = &stop;
  const RefineResult stopped = refineGc(space, problem, space.initial(), stopping);
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_LE(stopped.iterations, 1);
  // The run control's deadline ends it the same way, and its check hook runs on this thread.
  RefineOptions late{.max_iterations = 20};
  late.control.deadline = RunControl::Clock::now() - std::chrono::seconds(1);
  int checks = 0;
  late.control.on_check = [&] { ++checks; };
  const RefineResult expired = refineGc(space, problem, space.initial(), late);
  EXPECT_TRUE(expired.interrupted);
  EXPECT_LE(expired.iterations, 1);
  EXPECT_GE(checks, 1);
}
TEST(Refine, HoldsItsTimeBudget) {
  // Far from the truth on noisy data, with no tolerance and unlimited iterations: only the 2 s
  // budget ends it, across both stages and the map back.
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.3, 5), {});
  Trajectory data = test::pumaSearchTrajectory(8.0);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (Eigen::Index k = 0; k < data.q.size(); ++k) data.q.data()[k] += noise(rng);
  const GcProblem problem = makeGcProblem(data, {.num_segments = 60});
  const BaseCoordinates base = pumaBase(truth);
  RefineOptions options{.max_iterations = 1000000,
                        .function_tolerance = 0.0,
                        .gradient_tolerance = 0.0,
                        .parameter_tolerance = 0.0,
                        .max_seconds = 2.0};
  options.uncertainty = false;
  const RefineResult r = refineGc(space, problem, space.initial(), options, &base);
  // The budget, and at most one iteration (a 60-segment PUMA Jacobian, about 0.7 s here) and the
  // closing GC evaluation past it; 1 s leaves room for that and a loaded machine.
  std::string log = r.base_termination + " | " + r.termination + " |";
  for (const RefineIteration& it : r.history)
    log += " " + it.stage + ":" + std::to_string(it.seconds);
  EXPECT_LT(r.seconds, 2.0 + 1.0) << log;
  EXPECT_GT(r.seconds, 1.0) << r.termination;  // it used the budget rather than stopping at once
  EXPECT_TRUE(r.usable) << r.termination;
  EXPECT_FALSE(r.interrupted);  // the budget is not the run control
  EXPECT_LE(r.final_gc, r.initial_gc);
}

TEST(Refine, KeepsItsUncertaintyInsideTheBudget) {
  // A budget shorter than one Jacobian of the 60 segments (about 0.4 s here): the uncertainty
  // pass (another such Jacobian) would end past it, so it is skipped and the result says why;
  // before, it ran after the budget.
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.3, 5), {});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(8.0), {.num_segments = 60});
  const BaseCoordinates base = pumaBase(truth);
  RefineOptions options{.max_iterations = 1000000, .max_seconds = 0.2};
  const RefineResult r = refineGc(space, problem, space.initial(), options, &base);
  EXPECT_EQ(r.beta_std_dev.size(), 0) << r.termination;
  EXPECT_NE(r.uncertainty_skipped.find("raise the time budget"), std::string::npos)
      << r.uncertainty_skipped;
  EXPECT_LT(r.seconds, 0.2 + 1.0);  // the slack of HoldsItsTimeBudget
  // Without a budget it is computed, and nothing is said.
  options.max_seconds = 0.0;
  options.max_iterations = 1;
  const RefineResult unbounded = refineGc(space, problem, space.initial(), options, &base);
  EXPECT_EQ(unbounded.beta_std_dev.size(), base.projection.rows());
  EXPECT_TRUE(unbounded.uncertainty_skipped.empty()) << unbounded.uncertainty_skipped;
}

TEST(Refine, RefusesMismatchedInput) {
  const ParameterSpace space(makePuma560(), {});
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 2});
  EXPECT_THROW(refineGc(space, problem, Eigen::VectorXd::Zero(3), {}), InputError);
  for (const double weight : {-1.0, std::nan("")})
    EXPECT_THROW(refineGc(space, problem, space.initial(),
                          {.estimate_initial_states = true, .continuity_weight = weight}),
                 InputError)
        << weight;
}

}  // namespace
}  // namespace dynid
