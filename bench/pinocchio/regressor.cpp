// Pinocchio 3.7's joint torque regressor on the PUMA 560's kinematics (dynid's DH table, six
// revolute joints), to compare with bench_identification's BM_Regressor/drives:0 (6 x 60). Not
// part of the build: Pinocchio is not a Debian package. scripts/pinocchio-bench.sh builds it
// header-only against a Pinocchio source tree, with the same flags as dynid's Release build.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "bench/pinocchio/robots.hpp"
#include "pinocchio/algorithm/regressor.hpp"
#include "pinocchio/multibody/data.hpp"
#include "pinocchio/multibody/model.hpp"

namespace {
using peers::puma;

void BM_PinocchioRegressor(benchmark::State& state) {
  const pinocchio::Model model = puma();
  pinocchio::Data data(model);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int kStates = 64;
  std::vector<Eigen::VectorXd> q(kStates), v(kStates), a(kStates);
  for (int k = 0; k < kStates; ++k) {
    q[k] = Eigen::VectorXd(6), v[k] = Eigen::VectorXd(6), a[k] = Eigen::VectorXd(6);
    for (int j = 0; j < 6; ++j) q[k][j] = 2 * u(rng), v[k][j] = u(rng), a[k][j] = u(rng);
  }
  int k = 0;
  for (auto _ : state) {
    const auto& Y = pinocchio::computeJointTorqueRegressor(model, data, q[k], v[k], a[k]);
    benchmark::DoNotOptimize(Y.data());
    k = (k + 1) % kStates;
  }
}
BENCHMARK(BM_PinocchioRegressor);
}  // namespace

BENCHMARK_MAIN();
