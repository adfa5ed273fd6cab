// dynid prepare from a ROS 2 recording, as the CLI runs it: an hour (or less) of
// sensor_msgs/JointState at 1 kHz for a 7-joint arm (position, velocity and effort, names
// joint1..joint7, header stamps with +-0.1 ms jitter), in a rosbag2 SQLite file (.db3, written by
// SQLite) and in an MCAP file (unchunked, written here from the specification), read, cleaned,
// resampled, filtered, differentiated and written as train.csv, validate.csv, prepare.json and the
// figures. The recordings are written once per size, outside the timing. Counters: peak_rss_MB,
// the process's peak resident memory after the run (sizes and formats run in increasing order, so
// it is the largest so far); max_diff, the largest difference of the prepared train set from the
// same samples handed over as arrays (LogSource::arrays: the path a table takes after parsing).
// Run:
//   build/bench/bench_prepare_bag --benchmark_filter='/3600000'
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "analysis/logs/prepare.hpp"
#include "analysis/logs/read_log.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/scratch.hpp"
#include "reports/prepare_report.hpp"
#include "tests/common/joint_state_db3.hpp"

namespace {

using namespace dynid;

constexpr int kJoints = 7;
constexpr std::int64_t kEpoch = 1700000000LL * 1000000000LL;  // ns

/// Sample k: its header stamp [ns] and the joints' position, velocity and effort.
struct Sample {
  std::int64_t ns = 0;
  double q[kJoints], dq[kJoints], tau[kJoints];
};

class Samples {
 public:
  Sample next() {
    Sample s;
    s.ns = kEpoch + k_ * 1000000 + static_cast<std::int64_t>(std::llround(jitter_(rng_) * 1e9));
    const double t = static_cast<double>(s.ns - kEpoch) * 1e-9;
    for (int j = 0; j < kJoints; ++j) {
      const double w = (0.1 + 0.05 * (j + 1)) * 2 * M_PI;
      s.q[j] = 0.8 * std::sin(w * t + j + 1);
      s.dq[j] = 0.8 * w * std::cos(w * t + j + 1);
      s.tau[j] = 5.0 * std::sin(w * t + j + 1.3) + noise_(rng_);
    }
    ++k_;
    return s;
  }

 private:
  std::mt19937_64 rng_{3};
  std::uniform_real_distribution<double> jitter_{-1e-4, 1e-4}, noise_{-0.025, 0.025};
  std::int64_t k_ = 0;
};

std::vector<std::string> jointNames() {
  std::vector<std::string> names;
  for (int j = 1; j <= kJoints; ++j) names.push_back("joint" + std::to_string(j));
  return names;
}

std::string recordingPath(long samples, const char* extension) {
  return (std::filesystem::temp_directory_path() /
          ("dynid_bench_joint_states_" + std::to_string(samples) + extension))
      .string();
}

/// rosbag2's SQLite storage, written by SQLite.
std::string writeDb3(long samples) {
  const std::string path = recordingPath(samples, ".db3");
  if (std::filesystem::exists(path)) return path;
  const std::string work = path + ".partial";
  {
    test::JointStateDb3 db3(work);
    Samples source;
    const std::vector<std::string> names = jointNames();
    for (long k = 0; k < samples; ++k) {
      const Sample s = source.next();
      db3.add(s.ns, s.ns + 250000, names, s.q, s.dq, s.tau);  // received 0.25 ms after the stamp
    }
    db3.close();
  }
  std::filesystem::rename(work, path);
  return path;
}

/// An unchunked MCAP file (https://mcap.dev/spec): header, schema, channel, messages, data end,
/// footer.
std::string writeMcap(long samples) {
  const std::string path = recordingPath(samples, ".mcap");
  if (std::filesystem::exists(path)) return path;
  AtomicWriter out(path);
  const auto u16 = [](std::uint16_t v) { return std::string(reinterpret_cast<char*>(&v), 2); };
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<char*>(&v), 4); };
  const auto u64 = [](std::uint64_t v) { return std::string(reinterpret_cast<char*>(&v), 8); };
  const auto str = [&](const std::string& s) {
    return u32(static_cast<std::uint32_t>(s.size())) + s;
  };
  const auto record = [&](char op, const std::string& body) {
    out.write(std::string(1, op) + u64(body.size()) + body);
  };
  const std::string magic("\x89MCAP0\r\n", 8);
  out.write(magic);
  record(0x01, str("ros2") + str("dynid bench"));
  record(0x03, u16(1) + str("sensor_msgs/msg/JointState") + str("ros2msg") + str(""));
  record(0x04, u16(1) + u16(1) + str("/joint_states") + str("cdr") + u32(0));
  Samples source;
  test::CdrJointState cdr;
  const std::vector<std::string> names = jointNames();
  for (long k = 0; k < samples; ++k) {
    const Sample s = source.next();
    const auto receive = static_cast<std::uint64_t>(s.ns + 250000);
    record(0x05, u16(1) + u32(static_cast<std::uint32_t>(k)) + u64(receive) + u64(receive) +
                     cdr.encode(s.ns, names, s.q, s.dq, s.tau));
  }
  record(0x0F, u32(0));
  record(0x02, u64(0) + u64(0) + u32(0));
  out.write(magic);
  out.commit();
  return path;
}

/// The same samples as arrays (time relative to the first stamp, as a table is read).
std::shared_ptr<const RawSignals> arraysOf(long samples) {
  auto raw = std::make_shared<RawSignals>();
  raw->n = kJoints;
  raw->rows = samples;
  raw->has_dq = true;
  raw->values.resize(samples, 1 + 3 * kJoints);
  Samples source;
  std::int64_t first = 0;
  for (long k = 0; k < samples; ++k) {
    const Sample s = source.next();
    if (k == 0) first = s.ns;
    raw->values(k, 0) = static_cast<double>(s.ns - first) * 1e-9;
    for (int j = 0; j < kJoints; ++j) {
      raw->values(k, 1 + j) = s.q[j];
      raw->values(k, 1 + kJoints + j) = s.tau[j];
      raw->values(k, 1 + 2 * kJoints + j) = s.dq[j];
    }
  }
  raw->time_origin = static_cast<long double>(first) / 1e9L;
  raw->ddq_at = 1 + 3 * kJoints;
  raw->file = raw->tau_file = "arrays";
  raw->line_of = [](Eigen::Index k) { return static_cast<int>(k + 1); };
  return raw;
}

void BM_PrepareBag(benchmark::State& state, bool mcap) {
  const long samples = state.range(0);
  LogSource source;
  source.tables = {mcap ? writeMcap(samples) : writeDb3(samples)};
  // The log just written goes to disk before the timing: its write-back (a gigabyte for the hour)
  // would otherwise compete with the prepare being measured.
  ::sync();
  PrepareOptions options;
  options.validate_fraction = 0.2;
  const std::string dir =
      (std::filesystem::temp_directory_path() / "dynid_bench_prepared_bag").string();
  PrepareOutcome outcome;
  for (auto _ : state) {
    // As the CLI: the samples and the datasets in scratch files beside the output.
    outcome = prepareLog(source, options, 0, nearestExistingDirectory(dir));
    benchmark::DoNotOptimize(writePrepared(dir, source, options, outcome).size());
  }
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  state.counters["file_MB"] =
      static_cast<double>(std::filesystem::file_size(source.tables.front())) / (1 << 20);
  state.counters["samples_per_s"] = benchmark::Counter(
      static_cast<double>(samples), benchmark::Counter::kIsIterationInvariantRate);
  // Outside the timing: the same samples as arrays give the same datasets.
  LogSource arrays;
  arrays.arrays = arraysOf(samples);
  const PrepareOutcome reference = prepareLog(arrays, options);
  double diff = 0.0;
  Trajectory prepared;
  outcome.scratch_train->rows(0, static_cast<int>(outcome.trainSamples()), prepared);
  for (const auto& [a, b] : {std::pair{&prepared.q, &reference.train.q},
                             {&prepared.dq, &reference.train.dq},
                             {&prepared.ddq, &reference.train.ddq},
                             {&prepared.tau, &reference.train.tau}})
    diff = a->cols() == b->cols() ? std::max(diff, (*a - *b).cwiseAbs().maxCoeff())
                                  : std::numeric_limits<double>::infinity();
  state.counters["max_diff"] = diff;
  std::filesystem::remove_all(dir);
}
BENCHMARK_CAPTURE(BM_PrepareBag, db3, false)
    ->Arg(20000)
    ->Arg(360000)
    ->Arg(3600000)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_PrepareBag, mcap, true)
    ->Arg(20000)
    ->Arg(360000)
    ->Arg(3600000)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
