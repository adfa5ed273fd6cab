// Segment residual blocks evaluated on dynid's pool: the proxies give the cost functions' own
// values, fall back at another point, and a refinement gives the same bits for any thread count.
#include "search/refinement/evaluation.hpp"

#include <gtest/gtest.h>

#include <random>

#include <ceres/cost_function.h>

#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "search/refinement/costs.hpp"
#include "search/refinement/refine.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

Trajectory noisyPumaData(double duration) {
  Trajectory data = test::pumaSearchTrajectory(duration);
  std::mt19937_64 random(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (Eigen::Index k = 0; k < data.q.size(); ++k) {
    data.q.data()[k] += 1e-4 * gauss(random);
    data.dq.data()[k] += 1e-3 * gauss(random);
    data.tau.data()[k] += 0.05 * gauss(random);
  }
  return data;
}

/// Residuals and Jacobians of `cost` at `blocks` (all blocks' Jacobians).
struct Evaluated {
  bool ok = false;
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobians;
};
Evaluated evaluate(const ceres::CostFunction& cost, const std::vector<double*>& blocks,
                   bool with_jacobians) {
  Evaluated out;
  out.residuals.resize(static_cast<std::size_t>(cost.num_residuals()));
  std::vector<double*> jac;
  for (const int size : cost.parameter_block_sizes()) {
    out.jacobians.emplace_back(static_cast<std::size_t>(size * cost.num_residuals()));
    jac.push_back(out.jacobians.back().data());
  }
  std::vector<const double*> params(blocks.begin(), blocks.end());
  out.ok =
      cost.Evaluate(params.data(), out.residuals.data(), with_jacobians ? jac.data() : nullptr);
  if (!with_jacobians) out.jacobians.clear();
  return out;
}

TEST(ParallelSegmentEvaluation, ProxiesGiveTheCostFunctionsOwnValues) {
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.05, 9), {});
  const GcProblem problem = makeGcProblem(noisyPumaData(1.0), {.num_segments = 4});
  const RefineOptions options{.estimate_initial_states = true};
  Eigen::VectorXd x = space.initial();
  Eigen::MatrixXd starts(12, problem.numSegments());
  for (int s = 0; s < problem.numSegments(); ++s)
    starts.col(s) << problem.data.q.col(problem.starts[s]), problem.data.dq.col(problem.starts[s]);
  ThreadPool pool(2);
  ParallelSegmentEvaluation evaluation(pool);
  std::vector<std::unique_ptr<ceres::CostFunction>> direct, proxies;
  std::vector<std::vector<double*>> blocks;
  for (int s = 0; s < problem.numSegments(); ++s) {
    blocks.push_back(segmentBlocks(problem, options, s, x.data(), starts));
    direct.push_back(makeSegmentCost(truth, space, problem, s, true));
    proxies.push_back(
        evaluation.add(makeSegmentCost(truth, space, problem, s, true), blocks.back()));
  }
  evaluation.PrepareForEvaluation(true, true);
  EXPECT_EQ(evaluation.batches(), 1);
  for (int s = 0; s < problem.numSegments(); ++s) {
    const Evaluated want = evaluate(*direct[s], blocks[s], true);
    const Evaluated got = evaluate(*proxies[s], blocks[s], true);
    ASSERT_TRUE(want.ok);
    EXPECT_TRUE(got.ok);
    // The same computation on another thread: the same bits.
    EXPECT_EQ(got.residuals, want.residuals) << "segment " << s;
    EXPECT_EQ(got.jacobians, want.jacobians) << "segment " << s;
  }
  EXPECT_EQ(evaluation.fallbacks(), 0);
  // The same point again, residuals only: served from the cache, no new batch.
  evaluation.PrepareForEvaluation(false, false);
  EXPECT_EQ(evaluation.batches(), 1);
  // Another point without PrepareForEvaluation: the proxy evaluates it itself.
  x[0] *= 1.01;
  const Evaluated moved = evaluate(*proxies[0], blocks[0], false);
  EXPECT_EQ(evaluation.fallbacks(), 1);
  EXPECT_EQ(moved.residuals, evaluate(*direct[0], blocks[0], false).residuals);
  // After it, residuals without Jacobians for every segment, then Jacobians at the same point.
  evaluation.PrepareForEvaluation(false, true);
  EXPECT_EQ(evaluate(*proxies[1], blocks[1], false).residuals,
            evaluate(*direct[1], blocks[1], false).residuals);
  evaluation.PrepareForEvaluation(true, false);
  EXPECT_EQ(evaluation.batches(), 3);
  EXPECT_EQ(evaluate(*proxies[1], blocks[1], true).jacobians,
            evaluate(*direct[1], blocks[1], true).jacobians);
  EXPECT_EQ(evaluation.fallbacks(), 1);
}

TEST(ParallelSegmentEvaluation, RefinementsGiveTheSameBitsForAnyThreadCount) {
  // Noisy data and a far start (no exact fit, so the iterations differ in their last bits when
  // the sums do) and estimated starts: SPARSE_SCHUR for independent segments,
  // SPARSE_NORMAL_CHOLESKY for chained ones. With Ceres' own threads (commit 151845e), which sum
  // per thread, 1, 2 and 3 threads gave different bits here.
  const Model truth = makePuma560();
  const ParameterSpace space(perturbedModel(truth, 0.3, 3), {});
  for (const int segments : {10, 0}) {
    const GcProblem problem =
        makeGcProblem(noisyPumaData(segments == 0 ? 0.5 : 2.0), {.num_segments = segments});
    std::vector<RefineResult> results;
    for (const int threads : {1, 2, 3})
      results.push_back(
          refineGc(space, problem, space.initial(),
                   {.estimate_initial_states = true, .max_iterations = 2, .num_threads = threads}));
    for (std::size_t t = 1; t < results.size(); ++t) {
      EXPECT_EQ(results[t].final_gc, results[0].final_gc) << "segments " << segments;
      EXPECT_EQ(results[t].x, results[0].x) << "segments " << segments;
      EXPECT_EQ(results[t].initial_states, results[0].initial_states) << "segments " << segments;
    }
    EXPECT_LT(results[0].final_gc, results[0].initial_gc);
  }
}

}  // namespace
}  // namespace dynid
