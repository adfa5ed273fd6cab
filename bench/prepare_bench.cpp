// dynid prepare end to end, as the CLI runs it: a raw CSV log (7 joints, 1 kHz with jittered
// stamps, 15 columns) read, cleaned, resampled, filtered, differentiated and written as train.csv,
// validate.csv, prepare.json and the figures. The log is written once per size, outside the
// timing. peak_rss_MB is the process's peak resident memory after the run (sizes run in
// increasing order, so it is the largest size's); signals_MB the log's values as doubles. Run:
//   build/bench/bench_prepare --benchmark_filter=BM_Prepare/3600000
#include <sys/resource.h>
#include <unistd.h>

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include <benchmark/benchmark.h>

#include "analysis/logs/prepare.hpp"
#include "data/io.hpp"
#include "data/scratch.hpp"
#include "reports/prepare_report.hpp"

namespace {

using namespace dynid;

std::string writeLog(long samples) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("dynid_bench_log_" + std::to_string(samples) + ".csv"))
                               .string();
  if (std::filesystem::exists(path)) return path;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-1e-4, 1e-4), noise(-0.025, 0.025);
  AtomicWriter out(path);
  out.write("t,q1,q2,q3,q4,q5,q6,q7,tau1,tau2,tau3,tau4,tau5,tau6,tau7\n");
  std::array<char, 32> number;
  std::string row;
  const auto append = [&](double x) {
    row.append(number.data(), std::to_chars(number.data(), number.data() + 32, x).ptr);
  };
  for (long k = 0; k < samples; ++k) {
    const double t = k * 1e-3 + jitter(rng);
    row.clear();
    append(t);
    for (int j = 1; j <= 7; ++j) {
      row += ',';
      append(0.8 * std::sin((0.1 + 0.05 * j) * 2 * M_PI * t + j));
    }
    for (int j = 1; j <= 7; ++j) {
      row += ',';
      append(5.0 * std::sin((0.1 + 0.05 * j) * 2 * M_PI * t + j + 0.3) + noise(rng));
    }
    row += '\n';
    out.write(row);
  }
  out.commit();
  return path;
}

void BM_Prepare(benchmark::State& state) {
  const long samples = state.range(0);
  // The table, its time, q, dq (none) and tau columns; no per-signal files; joints from q.
  const LogSource source{
      {writeLog(samples)}, "t", "q*", "", "tau*", "", "", "", "", 0, false, "", ""};
  // The log just written goes to disk before the timing: its write-back (a gigabyte for the hour)
  // would otherwise compete with the prepare being measured.
  ::sync();
  PrepareOptions options;
  options.validate_fraction = 0.2;
  const std::string dir =
      (std::filesystem::temp_directory_path() / "dynid_bench_prepared").string();
  for (auto _ : state) {
    // As the CLI: the samples and the datasets in scratch files beside the output.
    const PrepareOutcome outcome = prepareLog(source, options, 0, nearestExistingDirectory(dir));
    benchmark::DoNotOptimize(writePrepared(dir, source, options, outcome).size());
  }
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  state.counters["signals_MB"] = static_cast<double>(samples) * 15 * 8 / 1e6 * 1e6 / (1 << 20);
  state.counters["samples_per_s"] = benchmark::Counter(
      static_cast<double>(samples), benchmark::Counter::kIsIterationInvariantRate);
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_Prepare)
    ->Arg(20000)
    ->Arg(360000)
    ->Arg(3600000)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
