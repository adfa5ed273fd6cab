// Pinocchio 3.7's CRBA, ABA and an RK4 step built on its ABA, on the PUMA 560's and the Panda's
// kinematics, to compare with bench_core's BM_Crba, BM_Aba, BM_Rk4Step (PUMA) and BM_CrbaPanda,
// BM_AbaPanda, BM_Rk4StepPanda. Not part of the build: scripts/pinocchio-bench.sh builds it
// header-only against a Pinocchio source tree, with the same flags as dynid's Release build.
// The states: 64 seeded random ones (q in [-2, 2], dq and tau in [-1, 1]), cycled, as bench_core.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "bench/pinocchio/robots.hpp"
#include "pinocchio/algorithm/aba.hpp"
#include "pinocchio/algorithm/crba.hpp"
#include "pinocchio/multibody/data.hpp"

namespace {

struct States {
  explicit States(int n) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < kCount; ++k) {
      q.emplace_back(n), v.emplace_back(n), tau.emplace_back(n);
      for (int j = 0; j < n; ++j) q[k][j] = 2 * u(rng), v[k][j] = u(rng), tau[k][j] = u(rng);
    }
  }
  static constexpr int kCount = 64;
  std::vector<Eigen::VectorXd> q, v, tau;
};

pinocchio::Model robot(int which) { return which == 0 ? peers::puma() : peers::panda(); }

void BM_PinocchioCrba(benchmark::State& state) {
  const pinocchio::Model model = robot(static_cast<int>(state.range(0)));
  pinocchio::Data data(model);
  const States s(model.nv);
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pinocchio::crba(model, data, s.q[k]).data());
    k = (k + 1) % States::kCount;
  }
}
BENCHMARK(BM_PinocchioCrba)->Arg(0)->Arg(1)->ArgName("panda");

void BM_PinocchioAba(benchmark::State& state) {
  const pinocchio::Model model = robot(static_cast<int>(state.range(0)));
  pinocchio::Data data(model);
  const States s(model.nv);
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pinocchio::aba(model, data, s.q[k], s.v[k], s.tau[k]).data());
    k = (k + 1) % States::kCount;
  }
}
BENCHMARK(BM_PinocchioAba)->Arg(0)->Arg(1)->ArgName("panda");

/// Classical RK4 on q, v with the torque held (revolute joints: q integrates as a vector), its
/// stage vectors preallocated, as dynid's rk4Step.
struct Rk4 {
  explicit Rk4(int n) : q_stage(n), v_stage(n), dq_sum(n), ddq_sum(n) {}
  void step(const pinocchio::Model& model, pinocchio::Data& data, Eigen::VectorXd& q,
            Eigen::VectorXd& v, const Eigen::VectorXd& tau, double h) {
    // k1
    ddq_sum = pinocchio::aba(model, data, q, v, tau);
    dq_sum = v;
    q_stage = q + h / 2 * v;
    v_stage = v + h / 2 * data.ddq;
    // k2, k3
    for (int stage = 0; stage < 2; ++stage) {
      pinocchio::aba(model, data, q_stage, v_stage, tau);
      dq_sum += 2 * v_stage;
      ddq_sum += 2 * data.ddq;
      const double f = stage == 0 ? h / 2 : h;
      q_stage = q + f * v_stage;
      v_stage = v + f * data.ddq;
    }
    // k4
    pinocchio::aba(model, data, q_stage, v_stage, tau);
    dq_sum += v_stage;
    ddq_sum += data.ddq;
    q += h / 6 * dq_sum;
    v += h / 6 * ddq_sum;
  }
  Eigen::VectorXd q_stage, v_stage, dq_sum, ddq_sum;
};

void BM_PinocchioRk4Step(benchmark::State& state) {
  const pinocchio::Model model = robot(static_cast<int>(state.range(0)));
  pinocchio::Data data(model);
  const States s(model.nv);
  Rk4 rk4(model.nv);
  Eigen::VectorXd q = s.q[0], v = s.v[0];
  int k = 0;
  for (auto _ : state) {
    // Restart from a stored state each step so the trajectory stays bounded.
    q = s.q[k];
    v = s.v[k];
    rk4.step(model, data, q, v, s.tau[k], 1e-3);
    benchmark::DoNotOptimize(q.data());
    k = (k + 1) % States::kCount;
  }
}
BENCHMARK(BM_PinocchioRk4Step)->Arg(0)->Arg(1)->ArgName("panda");

}  // namespace

BENCHMARK_MAIN();
