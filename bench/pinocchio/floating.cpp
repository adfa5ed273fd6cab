// Pinocchio 3.7's free-flyer inverse dynamics, regressor and mass matrix on the example robots
// (examples/floating/: ANYmal C, Romeo), loaded by Pinocchio's own URDF parser with a
// JointModelFreeFlyer root, to compare with bench_floating (the same 64 random states' kind: a
// random unit quaternion, twist, acceleration and joint values in +-1). Not part of the build:
// scripts/pinocchio-bench.sh builds it against a Pinocchio source tree and urdfdom.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "pinocchio/algorithm/crba.hpp"
#include "pinocchio/algorithm/regressor.hpp"
#include "pinocchio/algorithm/rnea.hpp"
#include "pinocchio/multibody/data.hpp"
#include "pinocchio/multibody/model.hpp"
#include "pinocchio/parsers/urdf.hpp"

namespace {

const char* const kRobots[] = {"examples/floating/anymal_c/anymal.urdf",
                               "examples/floating/romeo/romeo_small.urdf"};

pinocchio::Model robot(const benchmark::State& state) {
  pinocchio::Model model;
  pinocchio::urdf::buildModel(kRobots[state.range(0)], pinocchio::JointModelFreeFlyer(), model);
  return model;
}

struct States {
  std::vector<Eigen::VectorXd> q, v, a;
};

/// 64 states: q = (position, unit quaternion x y z w, joints), v and a (base linear, angular,
/// joints), all in +-1.
States randomStates(const pinocchio::Model& model) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  States s;
  for (int k = 0; k < 64; ++k) {
    Eigen::VectorXd q(model.nq), v(model.nv), a(model.nv);
    for (int i = 0; i < model.nq; ++i) q[i] = u(rng);
    q.segment<4>(3).normalize();
    for (int i = 0; i < model.nv; ++i) v[i] = u(rng), a[i] = u(rng);
    s.q.push_back(q), s.v.push_back(v), s.a.push_back(a);
  }
  return s;
}

/// Times `kernel(model, data, states, k)` (it returns a pointer to its result) over the 64 states.
template <typename Kernel>
void overStates(benchmark::State& state, Kernel kernel) {
  const pinocchio::Model model = robot(state);
  pinocchio::Data data(model);
  const States s = randomStates(model);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernel(model, data, s, k));
    k = (k + 1) % s.q.size();
  }
}

using Model = pinocchio::Model;
using Data = pinocchio::Data;

void BM_PinocchioFloatingRnea(benchmark::State& state) {
  overStates(state, [](const Model& m, Data& d, const States& s, std::size_t k) {
    return pinocchio::rnea(m, d, s.q[k], s.v[k], s.a[k]).data();
  });
}
BENCHMARK(BM_PinocchioFloatingRnea)->Arg(0)->Arg(1)->ArgName("robot");

void BM_PinocchioFloatingRegressor(benchmark::State& state) {
  overStates(state, [](const Model& m, Data& d, const States& s, std::size_t k) {
    return pinocchio::computeJointTorqueRegressor(m, d, s.q[k], s.v[k], s.a[k]).data();
  });
}
BENCHMARK(BM_PinocchioFloatingRegressor)->Arg(0)->Arg(1)->ArgName("robot");

void BM_PinocchioFloatingCrba(benchmark::State& state) {
  overStates(state, [](const Model& m, Data& d, const States& s, std::size_t k) {
    return pinocchio::crba(m, d, s.q[k]).data();
  });
}
BENCHMARK(BM_PinocchioFloatingCrba)->Arg(0)->Arg(1)->ArgName("robot");

}  // namespace

BENCHMARK_MAIN();
