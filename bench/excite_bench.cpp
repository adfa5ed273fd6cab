// dynid excite's design, as the CLI runs it with default settings: the built-in PUMA 560, 8
// multistart COBYLA starts of 2000 evaluations on a 25 Hz grid, the 1 kHz check and the scoring
// of the design and of the default sinusoid (every criterion, the exact GC Jacobian included),
// for each criterion, on 1 and 2 threads. Issue 18's target: one default design <= 60 s on 2
// cores. Run:
//   build/bench/bench_excite
#include <benchmark/benchmark.h>

#include "analysis/excitation/excite.hpp"
#include "data/puma560.hpp"

namespace {

using namespace dynid;

void BM_ExcitePuma(benchmark::State& state) {
  ExciteRequest request;
  request.robot = makePuma560(false);
  request.limits = excitationLimits(request.robot, {});
  request.criterion = static_cast<ExcitationCriterion>(state.range(0));
  request.threads = static_cast<int>(state.range(1));
  state.SetLabel(excitationCriterionName(request.criterion));
  double condition_unit = 0.0;
  long evaluations = 0;
  for (auto _ : state) {
    const ExciteOutcome out = exciteRun(request);
    condition_unit = out.score.condition_unit;
    evaluations = out.evaluations;
  }
  state.counters["condition_unit"] = condition_unit;
  state.counters["evaluations"] = static_cast<double>(evaluations);
}
BENCHMARK(BM_ExcitePuma)
    ->ArgNames({"criterion", "threads"})
    ->ArgsProduct({{static_cast<int>(ExcitationCriterion::kConditionUnit),
                    static_cast<int>(ExcitationCriterion::kRelativeSd),
                    static_cast<int>(ExcitationCriterion::kGc)},
                   {1, 2}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
