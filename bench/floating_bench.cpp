// The floating-base kernels on the example robots (examples/floating/): inverse dynamics, the
// regressor, the mass matrix and forward dynamics (by the mass matrix and by ABA) of ANYmal C (12
// joints) and Romeo (31 joints), each over 64 random states, as bench/pinocchio/floating.cpp times
// Pinocchio's free-flyer versions (scripts/pinocchio-bench.sh PINOCCHIO floating).
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "core/floating/floating_aba.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/regressor.hpp"
#include "core/rnea.hpp"
#include "data/urdf.hpp"

namespace {

using namespace dynid;

const char* const kRobots[] = {"examples/floating/anymal_c/anymal.urdf",
                               "examples/floating/romeo/romeo_small.urdf"};

struct States {
  std::vector<BaseMotion> base;
  std::vector<Eigen::VectorXd> q, dq, ddq;
};

/// 64 states: a random unit quaternion, twist, acceleration and joint values in +-1.
States randomStates(int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  States s;
  for (int k = 0; k < 64; ++k) {
    BaseMotion b;
    b.rotation = baseRotation(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized().eval());
    for (int i = 0; i < 6; ++i) b.twist[i] = u(rng), b.acceleration[i] = u(rng);
    s.base.push_back(b);
    Eigen::VectorXd q(n), dq(n), ddq(n);
    for (int i = 0; i < n; ++i) q[i] = u(rng), dq[i] = u(rng), ddq[i] = u(rng);
    s.q.push_back(q), s.dq.push_back(dq), s.ddq.push_back(ddq);
  }
  return s;
}

FloatingModel robot(const benchmark::State& state) {
  return loadFloatingUrdf(std::string(DYNID_SOURCE_DIR) + "/" + kRobots[state.range(0)]);
}

/// Times `kernel(model, data, states, k)` (it returns a pointer to its result) over the 64 states.
template <typename Kernel>
void overStates(benchmark::State& state, Kernel kernel) {
  const FloatingModel model = robot(state);
  FloatingData data(model);
  const States s = randomStates(model.numJoints());
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernel(model, data, s, k));
    k = (k + 1) % s.q.size();
  }
}

void BM_FloatingRnea(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return floatingRnea(m, d, s.base[k], s.q[k], s.dq[k], s.ddq[k]).data();
  });
}
BENCHMARK(BM_FloatingRnea)->Arg(0)->Arg(1)->ArgName("robot");

void BM_FloatingRegressor(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return floatingRegressor(m, d, s.base[k], s.q[k], s.dq[k], s.ddq[k]).data();
  });
}
BENCHMARK(BM_FloatingRegressor)->Arg(0)->Arg(1)->ArgName("robot");

void BM_FloatingCrba(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return floatingCrba(m, d, s.q[k]).data();
  });
}
BENCHMARK(BM_FloatingCrba)->Arg(0)->Arg(1)->ArgName("robot");

// Forward dynamics with the joint torques of the state's ddq column (any values do), no wrench.
void BM_FloatingForwardDynamics(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return floatingForwardDynamics(m, d, s.base[k], s.q[k], s.dq[k], s.ddq[k],
                                   Vector6<double>::Zero())
        .data();
  });
}
BENCHMARK(BM_FloatingForwardDynamics)->Arg(0)->Arg(1)->ArgName("robot");

void BM_FloatingAba(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return floatingAba(m, d, s.base[k], s.q[k], s.dq[k], s.ddq[k], Vector6<double>::Zero()).data();
  });
}
BENCHMARK(BM_FloatingAba)->Arg(0)->Arg(1)->ArgName("robot");

// The fixed-base kernels on the same limbs (the base held still), for scale.
void BM_FixedRneaOfLimbs(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return rnea(m.limbs(), d.limbs, s.q[k], s.dq[k], s.ddq[k]).data();
  });
}
BENCHMARK(BM_FixedRneaOfLimbs)->Arg(0)->Arg(1)->ArgName("robot");
void BM_FixedRegressorOfLimbs(benchmark::State& state) {
  overStates(state, [](const FloatingModel& m, FloatingData& d, const States& s, std::size_t k) {
    return jointTorqueRegressor(m.limbs(), d.limbs, s.q[k], s.dq[k], s.ddq[k]).data();
  });
}
BENCHMARK(BM_FixedRegressorOfLimbs)->Arg(0)->Arg(1)->ArgName("robot");

}  // namespace

BENCHMARK_MAIN();
