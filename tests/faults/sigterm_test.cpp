// Faults: `prepare` and `identify` stopped by SIGTERM (what Ctrl-C in a shell script, `timeout`
// or a scheduler sends) at random moments (seeded, so a failure can be replayed) while they
// rewrite an earlier run's output directory. Every time, the directory must hold the earlier
// run's whole set of files or the new run's whole set, never a mix (reports/output.hpp,
// OutputSet: the renames wait for the signal's handler).
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;
using test::run;

/// The files of `dir` (names and contents), the set records and temporaries left out.
std::map<std::string, std::string> contents(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename();
    if (name.rfind(".dynid-outputs", 0) == 0 || name.find(".tmp.") != std::string::npos) continue;
    files[name] = readFile(entry.path());
  }
  return files;
}

/// Runs `dynid ARGS` and sends SIGTERM after `seconds` (when still running); waits for it.
/// Returns the seconds it ran.
double terminateAfter(const std::string& args, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  const auto ran = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string line = "exec " + std::string(DYNID_BIN) + " " + args + " >/dev/null 2>&1";
    ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (ran() < seconds)
    if (::waitpid(pid, &status, WNOHANG) == pid)
      return ran();
    else
      std::this_thread::sleep_for(std::chrono::microseconds(200));
  ::kill(pid, SIGTERM);
  ::waitpid(pid, &status, 0);
  return ran();
}

/// Rewrites a copy of the `old_args` run's directory with `new_args` (both take "--out DIR" last)
/// and stops it at random moments between 30 % and 200 % of a whole run's length (the outputs
/// are written at its end; the length is the longest seen, as a loaded machine stretches it), for
/// at most 100 rounds or `budget` seconds; after each, the directory is one whole set. Returns
/// the rounds run.
int stopAtRandom(const std::string& old_args, const std::string& new_args, const std::string& name,
                 double budget) {
  const std::string old_dir = test::tempPath(name + "_old"), dir = test::tempPath(name + "_new");
  EXPECT_EQ(run(old_args + old_dir).code, 0);
  fs::copy(old_dir, dir);  // the new set written over the old one, as in every round
  double full = terminateAfter(new_args + dir, 60.0);
  const auto old_set = contents(old_dir), new_set = contents(dir);
  EXPECT_NE(old_set, new_set);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> fraction(0.3, 2.0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
  int rounds = 0, old_seen = 0, new_seen = 0;
  for (; rounds < 100 && std::chrono::steady_clock::now() < deadline; ++rounds) {
    fs::remove_all(dir);  // the same path every round: the outputs name their directory
    fs::copy(old_dir, dir);
    const double at = fraction(random) * full;
    if (const double ran = terminateAfter(new_args + dir, at); ran < at) full = std::max(full, ran);
    const auto now = contents(dir);
    const bool whole = now == old_set || now == new_set;
    EXPECT_TRUE(whole) << name << ": round " << rounds << " left a mix of the two sets";
    if (!whole) break;
    old_seen += now == old_set;
    new_seen += now == new_set;
  }
  // Both outcomes happen (the signal came before and after the publish), or the test proves
  // nothing about the moment in between.
  std::printf("%s: %d rounds, %d old, %d new, full run %.3f s\n", name.c_str(), rounds, old_seen,
              new_seen, full);
  EXPECT_GT(old_seen, 0) << name;
  EXPECT_GT(new_seen, 0) << name;
  return rounds;
}

TEST(SigTerm, PrepareLeavesTheOldSetOrTheNewOneNeverAMix) {
  std::ostringstream log;
  for (int k = 0; k < 3000; ++k) {
    const double t = k * 2e-3;
    log << t << " " << std::sin(t) << " " << std::cos(2.0 * t) << "\n";
  }
  const std::string path = test::tempPath("sigterm_log.txt");
  writeFileAtomically(path, log.str());
  const std::string common = "prepare --log " + path + " --q 2 --tau 3 ";
  const int rounds = stopAtRandom(common + "--validate-fraction 0.3 --out ",
                                  common + "--cutoff 5 --out ", "sigterm_prepare", 12.0);
  EXPECT_GE(rounds, 10);
}

TEST(SigTerm, IdentifyLeavesTheOldSetOrTheNewOneNeverAMix) {
  const std::string data = test::tempPath("sigterm_train.csv");
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --noise-tau 0.05 --out " + data).code, 0);
  const std::string common = "identify --robot puma560 --data " + data + " ";
  const int rounds = stopAtRandom(common + "--method ols --out ", common + "--method wls --out ",
                                  "sigterm_identify", 12.0);
  EXPECT_GE(rounds, 10);
}

}  // namespace
}  // namespace dynid
