// Ceres refinement of the GC error on the PUMA 560 (segments of 50 RK4 steps, 0.05 s at 1 kHz):
// the cost of one residual-and-Jacobian evaluation of a segment, and of one Levenberg-Marquardt
// iteration against the number of segments: starts measured, estimated independently (block-sparse
// Jacobian, Schur elimination of the starts), and estimated and chained (the segments are
// contiguous: multiple shooting, sparse Cholesky). Run:
//   build/bench/bench_refine --benchmark_repetitions=3 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>
#include <ceres/cost_function.h>

#include "bench/puma_problem.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "search/refinement/costs.hpp"
#include "search/refinement/refine.hpp"

namespace {

using namespace dynid;

using bench::pumaProblem;

// One segment's residuals and Jacobian (29 free paper parameters, optionally its 12-entry start).
void BM_SegmentJacobian(benchmark::State& state) {
  const bool with_start = state.range(0) != 0;
  const GcProblem problem = pumaProblem(1);
  const ParameterSpace space(perturbedModel(makePuma560(), 0.3, 1), {});
  const Model structure = space.modelAt(space.initial());
  const auto cost = makeSegmentCost(structure, space, problem, 0, with_start);
  Eigen::VectorXd start(12);
  start << problem.data.q.col(0), problem.data.dq.col(0);
  const double* parameters[2] = {space.initial().data(), start.data()};
  Eigen::VectorXd residuals(with_start ? 24 : 12);
  Eigen::MatrixXd jx(residuals.size(), space.numFree()), js(residuals.size(), 12);
  double* jacobians[2] = {jx.data(), js.data()};
  for (auto _ : state)
    benchmark::DoNotOptimize(cost->Evaluate(parameters, residuals.data(), jacobians));
  state.SetItemsProcessed(state.iterations() * problem.samples_per_segment);
}
BENCHMARK(BM_SegmentJacobian)->Arg(0)->Arg(1)->ArgName("with_start")->Unit(benchmark::kMillisecond);

// Five Levenberg-Marquardt iterations from a 30 % perturbation; time per iteration. starts: 0
// measured, 1 estimated independently, 2 estimated and chained.
void BM_RefineIterations(benchmark::State& state) {
  const int segments = static_cast<int>(state.range(0));
  const int starts = static_cast<int>(state.range(1));
  const GcProblem problem = pumaProblem(segments);
  const ParameterSpace space(perturbedModel(makePuma560(), 0.3, 1), {});
  RefineOptions options;
  options.estimate_initial_states = starts > 0;
  options.continuity_weight = starts == 2 ? 10.0 : 0.0;
  options.max_iterations = 5;
  options.function_tolerance = 0.0;
  options.parameter_tolerance = 0.0;
  int iterations = 0;
  for (auto _ : state) iterations += refineGc(space, problem, space.initial(), options).iterations;
  state.counters["seconds_per_iteration"] = benchmark::Counter(
      static_cast<double>(iterations), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RefineIterations)
    ->ArgsProduct({{10, 20, 40, 80}, {0, 1, 2}})
    ->ArgNames({"segments", "starts"})
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
