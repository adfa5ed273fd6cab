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
#include <sqlite3.h>
#include <sys/resource.h>

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
#include "reports/prepare_report.hpp"

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

/// The sample as a ROS 2 CDR sensor_msgs/JointState (little endian, XCDR1 alignment).
class CdrJointState {
 public:
  const std::string& encode(const Sample& s) {
    b_.assign("\x00\x01\x00\x00", 4);
    put<std::int32_t>(static_cast<std::int32_t>(s.ns / 1000000000));
    put<std::uint32_t>(static_cast<std::uint32_t>(s.ns % 1000000000));
    string("");
    put<std::uint32_t>(kJoints);
    for (int j = 1; j <= kJoints; ++j) string("joint" + std::to_string(j));
    for (const double* v : {s.q, s.dq, s.tau}) {
      put<std::uint32_t>(kJoints);
      for (int j = 0; j < kJoints; ++j) put<double>(v[j]);
    }
    return b_;
  }

 private:
  template <class T>
  void put(T v) {
    while ((b_.size() - 4) % sizeof(T) != 0) b_.push_back('\0');
    b_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void string(const std::string& s) {
    put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    b_.append(s);
    b_.push_back('\0');
  }
  std::string b_;
};

std::string recordingPath(long samples, const char* extension) {
  return (std::filesystem::temp_directory_path() /
          ("dynid_bench_joint_states_" + std::to_string(samples) + extension))
      .string();
}

void check(int rc, sqlite3* db) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE && rc != SQLITE_ROW)
    throw Error(std::string("sqlite: ") + sqlite3_errmsg(db));
}

/// rosbag2's SQLite storage, written by SQLite.
std::string writeDb3(long samples) {
  const std::string path = recordingPath(samples, ".db3");
  if (std::filesystem::exists(path)) return path;
  const std::string work = path + ".partial";
  std::filesystem::remove(work);
  sqlite3* db = nullptr;
  check(sqlite3_open(work.c_str(), &db), db);
  check(sqlite3_exec(db,
                     "PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;"
                     "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT "
                     "NOT NULL, serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT "
                     "NULL);"
                     "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
                     "timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
                     "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
                     "INSERT INTO topics VALUES (1, '/joint_states', "
                     "'sensor_msgs/msg/JointState', 'cdr', '');"
                     "BEGIN;",
                     nullptr, nullptr, nullptr),
        db);
  sqlite3_stmt* insert = nullptr;
  check(sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (1, ?, ?)",
                           -1, &insert, nullptr),
        db);
  Samples source;
  CdrJointState cdr;
  for (long k = 0; k < samples; ++k) {
    const Sample s = source.next();
    const std::string& bytes = cdr.encode(s);
    sqlite3_bind_int64(insert, 1, s.ns + 250000);  // received 0.25 ms after the stamp
    sqlite3_bind_blob(insert, 2, bytes.data(), static_cast<int>(bytes.size()), SQLITE_STATIC);
    check(sqlite3_step(insert), db);
    sqlite3_reset(insert);
  }
  sqlite3_finalize(insert);
  check(sqlite3_exec(db, "COMMIT;", nullptr, nullptr, nullptr), db);
  sqlite3_close(db);
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
  CdrJointState cdr;
  for (long k = 0; k < samples; ++k) {
    const Sample s = source.next();
    const auto receive = static_cast<std::uint64_t>(s.ns + 250000);
    record(0x05, u16(1) + u32(static_cast<std::uint32_t>(k)) + u64(receive) + u64(receive) +
                     cdr.encode(s));
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
  PrepareOptions options;
  options.validate_fraction = 0.2;
  const std::string dir =
      (std::filesystem::temp_directory_path() / "dynid_bench_prepared_bag").string();
  PrepareOutcome outcome;
  for (auto _ : state) {
    outcome = prepareLog(source, options);
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
  for (const auto& [a, b] : {std::pair{&outcome.train.q, &reference.train.q},
                             {&outcome.train.dq, &reference.train.dq},
                             {&outcome.train.ddq, &reference.train.ddq},
                             {&outcome.train.tau, &reference.train.tau}})
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
