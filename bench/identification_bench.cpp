// Identification on the PUMA 560, single-threaded: the regressor for one sample, and the whole
// least-squares identification from a 10 s, 1 kHz dataset (structural base parameters from random
// states, building W, OLS with covariance). Run:
//   build/bench/bench_identification --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include "core/parameters.hpp"
#include "core/regressor.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "identifiability/least_squares.hpp"

namespace {

using namespace dynid;

Trajectory pumaDataset(const Model& model, double duration) {
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.q0[2] = 1.5;
  r.amplitude = Eigen::VectorXd::Constant(6, 1.0);
  r.frequency = Eigen::VectorXd::LinSpaced(6, 0.23, 0.71);
  r.phase = Eigen::VectorXd::LinSpaced(6, 0.0, 2.5);
  TrackingController controller(model, r, defaultGains(model, r.q0, 8.0),
                                Eigen::VectorXd::Constant(6, 1e9));
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = 0.01;
  return simulate(model, controller, options);
}

void BM_Regressor(benchmark::State& state) {
  const Model model = makePuma560(true);
  Data data(model);
  const Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.3),
                        ddq = Eigen::VectorXd::Constant(6, -0.5);
  for (auto _ : state)
    benchmark::DoNotOptimize(jointTorqueRegressor(model, data, q, dq, ddq).data());
}
BENCHMARK(BM_Regressor);

void BM_IdentifyPuma(benchmark::State& state) {
  const Model model = makePuma560(state.range(1) != 0);
  const Trajectory dataset = pumaDataset(model, static_cast<double>(state.range(0)));
  const ParameterLayout layout = model.parameterLayout();
  for (auto _ : state) {
    // Structural base parameters, W from the dataset, OLS with covariance.
    const BaseParameters base = computeBaseParameters(
        observationFromRandomStates(model, std::max(100, 5 * layout.size() / 6), 1).W,
        standardParameterNames(layout), 0.0, defaultPreference(layout.num_links, layout.perLink()));
    const Observation train = observationFromTrajectory(model, dataset);
    benchmark::DoNotOptimize(
        estimateBaseParameters(base, train, LeastSquaresMethod::kOrdinary).beta.data());
  }
  state.counters["samples"] = static_cast<double>(dataset.numSamples());
}
BENCHMARK(BM_IdentifyPuma)
    ->Args({10, 0})
    ->Args({10, 1})
    ->ArgNames({"seconds", "drives"})
    ->Unit(benchmark::kMillisecond);

// Scaling with the number of samples (1e3 to 1e6 random states, rigid PUMA): building W (the
// regressor of every sample) and the base least squares (QR of the base columns, covariance).
// The structural base parameters are computed once, outside the timing.
void BM_ObservationAndQr(benchmark::State& state) {
  const Model model = makePuma560(false);
  const ParameterLayout layout = model.parameterLayout();
  const BaseParameters base = computeBaseParameters(
      observationFromRandomStates(model, 100, 1).W, standardParameterNames(layout), 0.0,
      defaultPreference(layout.num_links, layout.perLink()));
  const int samples = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const Observation observation = observationFromRandomStates(model, samples, 2);
    benchmark::DoNotOptimize(
        estimateBaseParameters(base, observation, LeastSquaresMethod::kOrdinary).beta.data());
  }
  state.SetItemsProcessed(state.iterations() * samples);
}
BENCHMARK(BM_ObservationAndQr)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->ArgName("samples")
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
