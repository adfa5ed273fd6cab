// Identification on the PUMA 560, single-threaded: the regressor for one sample, and the whole
// least-squares identification from a 10 s, 1 kHz dataset (structural base parameters from random
// states, building W, OLS with covariance); the CLI's own path from a CSV file to the estimate at
// 1e3 to 1e6 samples, and its parts (parsing; regressor + streamed factor update). Run:
//   build/bench/bench_identification --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <algorithm>
#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>

#include "analysis/runs/identify.hpp"
#include "analysis/runs/summarize.hpp"
#include "data/dataset_csv.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/least_squares_summary.hpp"
#include "identifiability/tall_qr.hpp"

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

// One state's joint torque regressor: rigid (6 x 60) and with the PUMA's drive terms (6 x 84).
void BM_Regressor(benchmark::State& state) {
  const Model model = makePuma560(state.range(0) != 0);
  Data data(model);
  const Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.3),
                        ddq = Eigen::VectorXd::Constant(6, -0.5);
  for (auto _ : state)
    benchmark::DoNotOptimize(jointTorqueRegressor(model, data, q, dq, ddq).data());
}
BENCHMARK(BM_Regressor)->Arg(0)->Arg(1)->ArgName("drives");

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
void sampleCounts(benchmark::internal::Benchmark* b) {
  for (int samples : {1000, 10000, 100000, 1000000}) b->Arg(samples);
  b->ArgName("samples")->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_ObservationAndQr)->Apply(sampleCounts);

/// A PUMA-with-drives dataset CSV of `samples` rows (1 kHz tracking, 0.01 N m noise), written
/// once per size into the temporary directory.
std::string datasetFile(const Model& model, long samples) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("dynid_bench_identify_" + std::to_string(samples) + ".csv"))
                               .string();
  if (!std::filesystem::exists(path))
    writeDatasetCsv(path, pumaDataset(model, static_cast<double>(samples - 1) * 1e-3));
  return path;
}

// `dynid identify --robot puma560 --drives --method ols --data FILE --threads T` as the CLI runs
// it (reports aside): structural base parameters, the file streamed through the factor in chunks,
// solve, the fit's series. (Peak memory: measure the CLI itself, `/usr/bin/time -f %M`; this
// process also holds the simulation that wrote the file.)
void BM_IdentifyFile(benchmark::State& state) {
  IdentifyRequest request;
  request.model = makePuma560(true);
  request.method = Method::kOls;
  request.data_file = datasetFile(request.model, state.range(0));
  request.threads = static_cast<int>(state.range(1));
  for (auto _ : state) {
    const IdentifyOutcome out = identifyRun(request);
    benchmark::DoNotOptimize(out.result.estimate.beta.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
// From 1e4: a shorter stretch of this motion does not reverse joint 1 (its Coulomb asymmetry is
// then unexcited, and identify refuses).
BENCHMARK(BM_IdentifyFile)
    ->ArgsProduct({{10000, 100000, 1000000}, {1, 2}})
    ->ArgNames({"samples", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The parts of the floor: parsing the same file alone (DatasetReader's chunks, as the CLI reads
// it), and the regressor and streamed factor update of every sample alone (no file).
void BM_ParseDataset(benchmark::State& state) {
  const std::string path = datasetFile(makePuma560(true), state.range(0));
  for (auto _ : state) {
    DatasetReader reader(path, 6);
    Trajectory chunk;
    while (reader.read(chunk, kStreamChunkSamples) > 0) benchmark::DoNotOptimize(chunk.q.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetBytesProcessed(state.iterations() *
                          static_cast<std::int64_t>(std::filesystem::file_size(path)));
}
BENCHMARK(BM_ParseDataset)->Arg(100000)->ArgName("samples")->Unit(benchmark::kMillisecond);

// The streamed factor's kernel alone: 1e5 random rows of `cols` columns (40: the PUMA's widest
// joint factor with drives, 39 base columns and the torque), in row-major chunks of 2048 as
// LeastSquaresStream hands them over; the counter is its 2 rows cols^2 flops per second.
void BM_TallQrUpdate(benchmark::State& state) {
  const auto cols = static_cast<Eigen::Index>(state.range(0));
  constexpr Eigen::Index kRows = 100000, kChunk = 2048;
  const TallQr::RowMajorMatrix rows = TallQr::RowMajorMatrix::Random(kRows, cols);
  for (auto _ : state) {
    TallQr factor(cols);
    for (Eigen::Index first = 0; first < kRows; first += kChunk)
      factor.addRowMajor(rows.middleRows(first, std::min(kChunk, kRows - first)));
    benchmark::DoNotOptimize(factor.r().data());
  }
  state.counters["flops"] =
      benchmark::Counter(2.0 * static_cast<double>(kRows) * static_cast<double>(cols * cols),
                         benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_TallQrUpdate)
    ->Arg(12)
    ->Arg(40)
    ->Arg(72)
    ->ArgName("cols")
    ->Unit(benchmark::kMillisecond);

// Chunks of kStreamChunkSamples through LeastSquaresStream::addTrajectory on T threads.
void BM_RegressorAndUpdate(benchmark::State& state) {
  const Model model = makePuma560(true);
  const Trajectory dataset = pumaDataset(model, static_cast<double>(state.range(0) - 1) * 1e-3);
  const BaseParameters base = structuralBaseParameters(model);
  ThreadPool pool(static_cast<int>(state.range(1)));
  std::vector<Trajectory> chunks;
  for (int first = 0; first < dataset.numSamples(); first += kStreamChunkSamples) {
    const int count = std::min(kStreamChunkSamples, dataset.numSamples() - first);
    chunks.push_back(dataset.samples(first, count));
  }
  for (auto _ : state) {
    LeastSquaresStream stream(base, model);
    for (const Trajectory& c : chunks) stream.addTrajectory(model, c, &pool);
    benchmark::DoNotOptimize(stream.factor().r_scaled.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_RegressorAndUpdate)
    ->ArgsProduct({{100000}, {1, 2}})
    ->ArgNames({"samples", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// `dynid summarize --robot puma560 --drives --data FILE --threads T` as the CLI runs it (the file
// written aside): the log's training set, the file streamed into its summary's batches.
void BM_SummarizeFile(benchmark::State& state) {
  SummarizeRequest request;
  request.model = makePuma560(true);
  request.data_files = {datasetFile(request.model, state.range(0))};
  request.threads = static_cast<int>(state.range(1));
  for (auto _ : state) {
    const SummarizeOutcome out = summarizeRun(request);
    benchmark::DoNotOptimize(out.summaries.front().factors.batches().data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SummarizeFile)
    ->ArgsProduct({{100000}, {1, 2}})
    ->ArgNames({"samples", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Its kernel without the file: chunks of kStreamChunkSamples through SummaryBuilder on T threads
// (the regressor of every sample, each joint's rows folded into its batch's factor).
void BM_SummaryBuild(benchmark::State& state) {
  const Model model = makePuma560(true);
  const Trajectory dataset = pumaDataset(model, static_cast<double>(state.range(0) - 1) * 1e-3);
  const BaseParameters base = structuralBaseParameters(model);
  ThreadPool pool(static_cast<int>(state.range(1)));
  std::vector<Trajectory> chunks;
  for (int first = 0; first < dataset.numSamples(); first += kStreamChunkSamples)
    chunks.push_back(
        dataset.samples(first, std::min(kStreamChunkSamples, dataset.numSamples() - first)));
  for (auto _ : state) {
    SummaryBuilder builder(base, model);
    for (const Trajectory& c : chunks) builder.addTrajectory(model, c, &pool);
    benchmark::DoNotOptimize(builder.finish().batches().data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SummaryBuild)
    ->ArgsProduct({{100000}, {1, 2}})
    ->ArgNames({"samples", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The floor's compute half: the joint torque regressor of every sample alone, one thread.
void BM_RegressorOnly(benchmark::State& state) {
  const Model model = makePuma560(true);
  const Trajectory dataset = pumaDataset(model, static_cast<double>(state.range(0) - 1) * 1e-3);
  Data data(model);
  for (auto _ : state)
    for (int k = 0; k < dataset.numSamples(); ++k)
      benchmark::DoNotOptimize(
          jointTorqueRegressor(model, data, dataset.q.col(k), dataset.dq.col(k), dataset.ddq.col(k))
              .data());
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_RegressorOnly)->Arg(100000)->ArgName("samples")->Unit(benchmark::kMillisecond);

// Merging two summaries of over half kMaxSummaryBatches batches each (a 20 s PUMA log's with drive
// terms, merged with itself): the batches appended and neighbours joined back below
// kMaxSummaryBatches, as a merge tree's upper levels do for every merge.
void BM_SummaryMerge(benchmark::State& state) {
  const Model model = makePuma560(true);
  const Trajectory dataset = pumaDataset(model, 20.0);
  const BaseParameters base = structuralBaseParameters(model);
  SummaryBuilder builder(base, model);
  builder.addTrajectory(model, dataset);
  LeastSquaresSummary full = builder.finish();
  while (2 * static_cast<int>(full.batches().size()) <= kMaxSummaryBatches) full.merge(full);
  for (auto _ : state) {
    LeastSquaresSummary merged = full;
    merged.merge(full);
    benchmark::DoNotOptimize(merged.batches().data());
  }
}
BENCHMARK(BM_SummaryMerge)->Unit(benchmark::kMillisecond);

// The join of two batches' factors of one joint (n x n upper triangular, n the support and the
// torque column): the dense reduction of their 2n rows (TallQr, the merge's kernel before) and
// the triangular one (stackedTriangularFactor).
void BM_FactorJoin(benchmark::State& state) {
  const Eigen::Index n = state.range(0);
  TallQr x(n), y(n);
  x.add(Eigen::MatrixXd::Random(4 * n, n));
  y.add(Eigen::MatrixXd::Random(4 * n, n));
  const Eigen::MatrixXd a = x.r(), b = y.r();
  for (auto _ : state) {
    if (state.range(1) == 0) {
      TallQr qr(n, 2 * n);
      qr.add(a);
      qr.add(b);
      benchmark::DoNotOptimize(qr.r().data());
    } else {
      benchmark::DoNotOptimize(stackedTriangularFactor(a, b).data());
    }
  }
}
BENCHMARK(BM_FactorJoin)->ArgsProduct({{20, 65}, {0, 1}})->ArgNames({"n", "triangular"});

}  // namespace

BENCHMARK_MAIN();
