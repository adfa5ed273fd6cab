// Faults: `search`, `refine` and `batch` killed with SIGKILL at random moments (seeded, so a
// failure can be replayed), as a crash, the OOM killer or a cluster scheduler would. After every
// kill, no output in the run's directory may be corrupt (a file is whole or absent; stale
// `*.tmp.<pid>` temporaries are the only leftovers), and running the same command again must
// finish cleanly with what the docs promise: a search resumed from its checkpoint ends exactly
// where an uninterrupted run ends (docs/SEARCH.md), a batch finishes only the missing runs and its
// table equals an uninterrupted one (docs/BATCH.md), and an output that existed before a killed
// run is still a whole file.
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/processes.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;
using test::run;

/// dynid ARGS in a process group of its own (so a kill reaches batch's workers too), output
/// discarded. Returns its pid.
pid_t start(const std::string& args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    const std::string line = "exec " + std::string(DYNID_BIN) + " " + args + " >/dev/null 2>&1";
    ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: the kill may come before the child ran setpgid
  return pid;
}

/// Waits `seconds`, then SIGKILLs the group. True when the run was killed, false when it had
/// already finished (then its exit status must be 0).
bool killAfter(pid_t pid, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < until) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the run failed by itself";
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return true;
}

/// Seconds a complete run of `args` takes.
double timed(const std::string& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const test::Result r = run(args);
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Every file under dir is whole: JSON parses, a CSV's rows all have the header's field count and
/// end with a newline, nothing is empty. Temporaries (*.tmp.<pid>) are skipped: nothing reads them.
void expectNothingCorrupt(const std::string& dir) {
  if (!fs::exists(dir)) return;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string path = entry.path().string();
    if (path.find(".tmp.") != std::string::npos) continue;
    const std::string text = readFile(path);
    EXPECT_FALSE(text.empty()) << path << " is empty";
    if (entry.path().extension() == ".json" || entry.path().extension() == ".ckpt") {
      EXPECT_TRUE(nlohmann::json::accept(text)) << path << " is not whole JSON";
    } else if (entry.path().extension() == ".csv") {
      EXPECT_EQ(text.back(), '\n') << path << " does not end with a newline";
      std::istringstream lines(text);
      std::string line;
      std::getline(lines, line);
      const auto fields = std::count(line.begin(), line.end(), ',');
      while (std::getline(lines, line))
        EXPECT_EQ(std::count(line.begin(), line.end(), ','), fields) << path << ": a short row";
    }
  }
}

/// The dataset the runs share, made once.
const std::string& dataset() {
  static const std::string path = [] {
    const std::string p = test::tempPath("faults_train.csv");
    EXPECT_EQ(run("simulate --robot puma560 --duration 3 --out " + p).code, 0);
    return p;
  }();
  return path;
}

nlohmann::json jsonOf(const std::string& path) { return nlohmann::json::parse(readFile(path)); }

class SigKill : public ::testing::TestWithParam<std::string> {};

// A search killed again and again, then finished from its checkpoint, ends exactly where an
// uninterrupted run ends.
TEST_P(SigKill, SearchResumesFromItsCheckpointToTheUninterruptedResult) {
  const std::string method = GetParam();
  // Each method's own options only (an option a method ignores is a usage error).
  const std::string own = method == "ga"    ? "--population 8 "
                          : method == "nlo" ? "--evals-per-seed 40 "
                                            : "--population 8 --evals-per-seed 40 ";
  const std::string common = "search --method " + method + " --robot puma560 --data " + dataset() +
                             " --perturb 0.3 --seed 4 --segments 20 --threads 1 " + own +
                             "--budget-evals 480 ";
  const std::string reference = test::tempPath("faults_reference_" + method);
  double seconds = timed(common + "--checkpoint " + reference + ".ckpt --out " + reference);
  const std::string dir = test::tempPath("faults_search_" + method);
  const std::string checkpoint = dir + "/search.ckpt";
  fs::create_directories(dir);
  std::mt19937 rng(method == "ga" ? 17 : 23);
  // From the very start: a kill right after the first checkpoint (round 0) must resume too.
  std::uniform_real_distribution<double> fraction(0.0, 0.95);
  int kills = 0;
  for (int attempt = 0; attempt < 8 && kills < 5; ++attempt) {
    const double at = fraction(rng) * seconds;
    SCOPED_TRACE("killed after " + std::to_string(at) + " s of a " + std::to_string(seconds) +
                 " s run");
    if (!killAfter(start(common + "--checkpoint " + checkpoint + " --out " + dir + "/out"), at)) {
      if (kills > 0) break;  // resumed to the end: the rest is checked below
      // Finished before its first kill: the reference was timed on a busier machine. Start over
      // with half the window (a finished checkpoint leaves nothing to kill).
      fs::remove_all(dir);
      fs::create_directories(dir);
      seconds *= 0.5;
      continue;
    }
    ++kills;
    expectNothingCorrupt(dir);
  }
  EXPECT_GE(kills, 1) << "every run finished before its kill: nothing was tested";
  const test::Result last = run(common + "--checkpoint " + checkpoint + " --out " + dir + "/out");
  ASSERT_EQ(last.code, 0) << last.err;
  expectNothingCorrupt(dir);
  const nlohmann::json a = jsonOf(reference + "/search.json"), b = jsonOf(dir + "/out/search.json");
  EXPECT_EQ(a["estimate"], b["estimate"]);
  EXPECT_EQ(a["final_gc_error"], b["final_gc_error"]);
  EXPECT_EQ(a["evaluations"], b["evaluations"]);
  EXPECT_EQ(a["history"].size(), b["history"].size());
  // The next run's commits removed the killed runs' temporaries of the same files.
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
}

INSTANTIATE_TEST_SUITE_P(Methods, SigKill, ::testing::Values("ga", "nlo", "hybrid"));

// A refinement killed while it rewrites an existing result leaves the old result whole; the next
// run writes the same result as an uninterrupted one.
TEST(SigKillRefine, AnExistingResultStaysWholeAndTheRerunMatches) {
  const std::string search = test::tempPath("faults_refine_search");
  ASSERT_EQ(run("search --method nlo --robot puma560 --data " + dataset() +
                " --perturb 0.3 --seed 2 --segments 20 --budget-evals 60 --out " + search)
                .code,
            0);
  const std::string args = "refine --robot puma560 --from " + search + "/search.json --data " +
                           dataset() + " --threads 1 --max-iterations 3 --no-base-stage --out ";
  const std::string reference = test::tempPath("faults_refine_reference");
  const double seconds = timed(args + reference);
  const std::string dir = test::tempPath("faults_refine");
  ASSERT_EQ(run(args + dir).code, 0);
  std::map<std::string, std::string> before;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) before[entry.path().string()] = readFile(entry.path().string());
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> moment(0.05 * seconds, 1.2 * seconds);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double at = moment(rng);
    SCOPED_TRACE("killed after " + std::to_string(at) + " s");
    killAfter(start(args + dir), at);
    expectNothingCorrupt(dir);
    for (const auto& [path, text] : before) EXPECT_TRUE(fs::exists(path)) << path << " is gone";
  }
  ASSERT_EQ(run(args + dir).code, 0);
  const std::string name = "/refine.json";
  ASSERT_TRUE(fs::exists(reference + name));
  EXPECT_EQ(jsonOf(reference + name)["final_gc_error"], jsonOf(dir + name)["final_gc_error"]);
  EXPECT_EQ(jsonOf(reference + name)["estimate"], jsonOf(dir + name)["estimate"]);
}

// A batch killed with its workers, again and again, finishes only the missing runs; its table
// equals an uninterrupted batch's.
TEST(SigKillBatch, FinishesTheMissingRunsToTheUninterruptedTable) {
  const std::string manifest = test::tempPath("faults_manifest.json");
  std::ofstream(manifest) << R"({"schema_version": 1,
    "grid": {"method": ["ols", "nlo"], "seed": [1, 2, 3]},
    "fixed": {"train_seconds": 2, "test_seconds": 2, "segments": 10, "search_seconds": 0,
              "search_evaluations": 60, "refine_iterations": 5}})";
  const std::string reference = test::tempPath("faults_batch_reference");
  const double seconds = timed("batch " + manifest + " --jobs 2 --out " + reference);
  const std::string dir = test::tempPath("faults_batch");
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> moment(0.05 * seconds, 0.9 * seconds);
  int kills = 0;
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double at = moment(rng);
    SCOPED_TRACE("killed after " + std::to_string(at) + " s of " + std::to_string(seconds));
    if (!killAfter(start("batch " + manifest + " --jobs 2 --out " + dir), at)) break;
    ++kills;
    expectNothingCorrupt(dir);
  }
  EXPECT_GE(kills, 1);
  const test::Result last = run("batch " + manifest + " --jobs 2 --out " + dir);
  ASSERT_EQ(last.code, 0) << last.err;
  expectNothingCorrupt(dir);
  const nlohmann::json a = jsonOf(reference + "/results.json"), b = jsonOf(dir + "/results.json");
  ASSERT_EQ(a["rows"].size(), 6u);
  ASSERT_EQ(b["rows"].size(), 6u);
  for (std::size_t i = 0; i < 6; ++i)
    for (const char* metric :
         {"run", "gc_error_train", "gc_error_test", "base_param_error", "evaluations"})
      EXPECT_EQ(a["rows"][i][metric], b["rows"][i][metric]) << "row " << i << " " << metric;
}

// A batch killed alone (SIGKILL to its pid, not its group: a scheduler, the OOM killer) takes its
// workers with it instead of leaving them running to the end of their runs.
TEST(SigKillBatch, WorkersEndWithTheirParent) {
  const std::string manifest = test::writeTemp("faults_orphans.json", R"({"schema_version": 1,
    "grid": {"method": ["nlo", "ga"], "seed": [1, 2]},
    "fixed": {"train_seconds": 3, "test_seconds": 2, "segments": 10, "search_seconds": 0,
              "search_evaluations": 2000, "refine_iterations": 50}})");
  const std::string dir = test::tempPath("faults_orphans");
  const pid_t pid = start("batch " + manifest + " --jobs 2 --out " + dir);
  // Wait until both workers run (each names its result file under dir/runs).
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (test::processesMentioning(dir + "/runs/") < 2 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(test::processesMentioning(dir + "/runs/"), 2) << "the workers never started";
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_EQ(test::waitUntilNoneMention(dir + "/runs/", 10.0), 0) << "workers outlived their batch";
  ::kill(-pid, SIGKILL);  // whatever is left, so the suite does not wait for it
}

}  // namespace
}  // namespace dynid
