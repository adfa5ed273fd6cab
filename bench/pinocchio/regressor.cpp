// Pinocchio 3.7's joint torque regressor on the PUMA 560's kinematics (dynid's DH table, six
// revolute joints), to compare with bench_identification's BM_Regressor/drives:0 (6 x 60). Not
// part of the build: Pinocchio is not a Debian package. scripts/pinocchio-regressor.sh builds it
// header-only against a Pinocchio source tree, with the same flags as dynid's Release build.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "pinocchio/algorithm/regressor.hpp"
#include "pinocchio/multibody/data.hpp"
#include "pinocchio/multibody/model.hpp"

namespace {
pinocchio::Model puma() {
  struct Dh {
    double d, a, alpha;
  };
  const double pi = std::numbers::pi;
  const Dh dh[6] = {{0.0, 0.0, pi / 2},    {0.0, 0.4318, 0.0},  {0.15005, 0.0203, -pi / 2},
                    {0.4318, 0.0, pi / 2}, {0.0, 0.0, -pi / 2}, {0.0, 0.0, 0.0}};
  pinocchio::Model model;
  pinocchio::JointIndex parent = 0;
  pinocchio::SE3 placement = pinocchio::SE3::Identity();
  for (int i = 0; i < 6; ++i) {
    parent = model.addJoint(parent, pinocchio::JointModelRZ(), placement,
                            "joint" + std::to_string(i + 1));
    model.appendBodyToJoint(parent, pinocchio::Inertia::Random(), pinocchio::SE3::Identity());
    const double ca = dh[i].alpha == 0.0 ? 1.0 : 0.0,
                 sa = dh[i].alpha > 0 ? 1.0 : (dh[i].alpha < 0 ? -1.0 : 0.0);
    Eigen::Matrix3d r;
    r << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    placement = pinocchio::SE3(r, Eigen::Vector3d(dh[i].a, 0.0, dh[i].d));
  }
  model.gravity.linear() << 0, 0, -9.81;
  return model;
}

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
