// Core dynamics on the built-in PUMA 560, single-threaded, at seeded random states within the
// joint limits. Run: build/bench/bench_core --benchmark_repetitions=5
// --benchmark_report_aggregates_only
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/integrators.hpp"
#include "core/rnea.hpp"
#include "core/sin_cos.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"

namespace {

using dynid::Data;
using dynid::Model;

/// 64 seeded random states (q within limits, dq and ddq in [-2, 2]); benchmarks cycle through them
/// so branch predictors and caches see varied inputs.
struct States {
  explicit States(const Model& model) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < kCount; ++k) {
      Eigen::VectorXd q(model.numJoints()), dq(model.numJoints()), ddq(model.numJoints());
      for (int i = 0; i < model.numJoints(); ++i) {
        q[i] = u(rng) * model.limits[i].upper;
        dq[i] = 2.0 * u(rng);
        ddq[i] = 2.0 * u(rng);
      }
      this->q.push_back(q), this->dq.push_back(dq), this->ddq.push_back(ddq);
    }
  }
  static constexpr int kCount = 64;
  std::vector<Eigen::VectorXd> q, dq, ddq;
};

void BM_Rnea(benchmark::State& state) {
  const Model model = dynid::makePuma560(state.range(0) != 0);
  Data data(model);
  const States s(model);
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(dynid::rnea(model, data, s.q[k], s.dq[k], s.ddq[k]).data());
    k = (k + 1) % States::kCount;
  }
}
BENCHMARK(BM_Rnea)->Arg(0)->Arg(1)->ArgName("drives");

// The C++ loop that the Python module's batched rnea is compared with (bench/python_rnea.py):
// 1e6 states in row-major N x n arrays (NumPy's layout), torques written to another, one thread.
void BM_RneaBatch(benchmark::State& state) {
  const Model model = dynid::makePuma560(false);
  const int n = model.numJoints();
  const Eigen::Index count = state.range(0);
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Rows q(count, n), dq(count, n), ddq(count, n), tau(count, n);
  for (Rows* m : {&q, &dq, &ddq})
    for (Eigen::Index k = 0; k < m->size(); ++k) m->data()[k] = u(rng);
  Data data(model);
  using Row = Eigen::Map<const Eigen::VectorXd>;
  for (auto _ : state) {
    for (Eigen::Index k = 0; k < count; ++k)
      Eigen::Map<Eigen::VectorXd>(tau.data() + k * n, n) =
          dynid::rnea(model, data, Row(q.data() + k * n, n), Row(dq.data() + k * n, n),
                      Row(ddq.data() + k * n, n));
    benchmark::DoNotOptimize(tau.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * count);
}
BENCHMARK(BM_RneaBatch)->Arg(1000000)->ArgName("states")->Unit(benchmark::kMillisecond);

void crbaLoop(benchmark::State& state, const Model& model) {
  Data data(model);
  const States s(model);
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(dynid::crba(model, data, s.q[k]).data());
    k = (k + 1) % States::kCount;
  }
}
void BM_Crba(benchmark::State& state) { crbaLoop(state, dynid::makePuma560(false)); }

/// The PUMA's six joint angles' sines and cosines as CRBA waits on them: each call's arguments
/// depend on the previous call's results (q + 1e-300 sin q, which is q), so this is latency, not
/// throughput. isa: sinCosBlock (core/sin_cos.hpp) on SSE2 (0), AVX2 (1), AVX-512 (2); -1: six
/// calls of the C library's sincos, as CRBA made before.
void BM_SinCosPuma(benchmark::State& state) {
  const int isa = static_cast<int>(state.range(0));
  if (isa > dynid::cpuLaneIsa()) {
    state.SkipWithError("this CPU or build lacks the instruction set");
    return;
  }
  const States s(dynid::makePuma560(false));
  dynid::SinCosBlock block{};
  int k = 0;
  for (auto _ : state) {
    double x[6];
    for (int i = 0; i < 6; ++i) x[i] = s.q[k][i] + 1e-300 * block.s[i];
    if (isa < 0)
      for (int i = 0; i < 6; ++i) ::sincos(x[i], &block.s[i], &block.c[i]);
    else
      dynid::sinCosBlock(x, 6, block, isa);
    benchmark::DoNotOptimize(block);
    k = (k + 1) % States::kCount;
  }
}
BENCHMARK(BM_SinCosPuma)->DenseRange(-1, 2)->ArgName("isa");
BENCHMARK(BM_Crba);
// The Panda (7 joints, modified DH) beside the PUMA, for scripts/pinocchio-bench.sh.
void BM_CrbaPanda(benchmark::State& state) { crbaLoop(state, dynid::makePanda(false)); }
BENCHMARK(BM_CrbaPanda);

/// The PUMA with ABA's permuted transform path switched off (placement_permutation = -1), as for
/// a robot whose joint placements are not exact signed permutations (e.g. a URDF's rpy of
/// 1.5707963 rad, whose cosine is 6e-17).
Model generalPuma(bool drives) {
  Model model = dynid::makePuma560(drives);
  model.setPermutedPlacements(false);
  return model;
}

void abaLoop(benchmark::State& state, const Model& model) {
  Data data(model);
  const States s(model);
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(dynid::aba(model, data, s.q[k], s.dq[k], s.ddq[k]).data());
    k = (k + 1) % States::kCount;
  }
}
void BM_Aba(benchmark::State& state) { abaLoop(state, dynid::makePuma560(state.range(0) != 0)); }
BENCHMARK(BM_Aba)->Arg(0)->Arg(1)->ArgName("drives");
void BM_AbaPanda(benchmark::State& state) { abaLoop(state, dynid::makePanda(false)); }
BENCHMARK(BM_AbaPanda);
void BM_AbaGeneralPlacements(benchmark::State& state) { abaLoop(state, generalPuma(false)); }
BENCHMARK(BM_AbaGeneralPlacements);

void rk4Loop(benchmark::State& state, const Model& model) {
  Data data(model);
  const States s(model);
  Eigen::VectorXd q = s.q[0], dq = s.dq[0];
  int k = 0;
  for (auto _ : state) {
    // Restart from a stored state each step so the trajectory stays bounded.
    q = s.q[k];
    dq = s.dq[k];
    dynid::rk4Step(model, data, q, dq, s.ddq[k], 1e-3);
    benchmark::DoNotOptimize(q.data());
    k = (k + 1) % States::kCount;
  }
}
void BM_Rk4Step(benchmark::State& state) { rk4Loop(state, dynid::makePuma560(false)); }
BENCHMARK(BM_Rk4Step);
void BM_Rk4StepPanda(benchmark::State& state) { rk4Loop(state, dynid::makePanda(false)); }
BENCHMARK(BM_Rk4StepPanda);
void BM_Rk4StepGeneralPlacements(benchmark::State& state) { rk4Loop(state, generalPuma(false)); }
BENCHMARK(BM_Rk4StepGeneralPlacements);

}  // namespace

BENCHMARK_MAIN();
