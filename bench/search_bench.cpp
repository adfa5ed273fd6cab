// GC-error evaluation on the PUMA 560: segments of 50 RK4 steps (0.05 s at 1 kHz) of a candidate
// model 30 % off, 1 to 10,000 segments, with 1 and 2 threads. items_per_second counts RK4 steps.
// Run:
//   build/bench/bench_search --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include "bench/puma_problem.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "search/gc_error.hpp"

namespace {

using namespace dynid;

using bench::pumaProblem;

void BM_GcError(benchmark::State& state) {
  const int segments = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  const GcProblem problem = pumaProblem(segments);
  const Model candidate = perturbedModel(makePuma560(), 0.3, 1);
  ThreadPool pool(threads);
  GcWorkspace workspace(threads);
  for (auto _ : state) benchmark::DoNotOptimize(gcError(candidate, problem, workspace, pool));
  state.SetItemsProcessed(state.iterations() * segments * problem.samples_per_segment);
}
// Scaling: 1 to 10,000 segments of 50 steps, 1 and 2 threads (docs/PERFORMANCE.md).
BENCHMARK(BM_GcError)
    ->ArgsProduct({{1, 10, 100, 1000, 10000}, {1, 2}})
    ->ArgNames({"segments", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same evaluation, 100 segments on one thread, with 1 (the scalar path), 2, 4 and 8 lanes
// (core/lanes.hpp): interleave with --benchmark_enable_random_interleaving.
void BM_GcErrorLanes(benchmark::State& state) {
  const int lanes = static_cast<int>(state.range(0));
  const GcProblem problem = pumaProblem(100);
  const Model candidate = perturbedModel(makePuma560(), 0.3, 1);
  ThreadPool pool(1);
  GcWorkspace workspace(1, lanes);
  for (auto _ : state) benchmark::DoNotOptimize(gcError(candidate, problem, workspace, pool));
  state.SetItemsProcessed(state.iterations() * 100 * problem.samples_per_segment);
}
BENCHMARK(BM_GcErrorLanes)
    ->ArgName("lanes")
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(8)
    ->Unit(benchmark::kMillisecond);

// 4 lanes in each instruction set (core/lanes.hpp: 0 the build's, 1 AVX2, 2 AVX-512; the lanes
// rows above take the widest this build and CPU offer, gcLaneIsa()); a set the CPU or the build
// lacks is reported as skipped.
void BM_GcErrorLanesIsa(benchmark::State& state) {
  const int isa = static_cast<int>(state.range(0));
  if (isa > gcLaneIsa()) {
    state.SkipWithError("this build or CPU has no rollout for that instruction set");
    return;
  }
  const GcProblem problem = pumaProblem(100);
  const Model candidate = perturbedModel(makePuma560(), 0.3, 1);
  ThreadPool pool(1);
  GcWorkspace workspace(1, 4);
  workspace.lane_isa = isa;
  for (auto _ : state) benchmark::DoNotOptimize(gcError(candidate, problem, workspace, pool));
  state.SetItemsProcessed(state.iterations() * 100 * problem.samples_per_segment);
}
BENCHMARK(BM_GcErrorLanesIsa)->ArgName("isa")->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
