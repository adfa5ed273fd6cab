// dynid search: history, checkpoints and resuming, SIGINT, usage errors.
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, SearchWritesHistoryAndResumesFromACheckpoint) {
  const std::string train = test::tempPath("search_train.csv"), dir = test::tempPath("search");
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + train).code, 0);
  const std::string common = "search --robot puma560 --data " + train +
                             " --perturb 0.3 --truth puma560 --seed 1 --segments 8 --threads 2 ";
  const Result r = run(common + "--method ga --population 10 --budget-evals 60 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/search.json"));
  for (const char* key :
       {"schema_version", "method", "settings", "initial_gc_error", "final_gc_error", "estimate",
        "history", "evaluations", "seconds", "termination", "final_parameter_error"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["termination"], "evaluations");
  EXPECT_LE(j["final_gc_error"].get<double>(), j["initial_gc_error"].get<double>());
  EXPECT_EQ(j["estimate"]["paper"].size(), 42u);
  EXPECT_EQ(j["estimate"]["standard"].size(), 60u);
  EXPECT_TRUE(j["history"][0].contains("min_parameter_error"));
  // A run stopped at 30 evaluations and resumed to 60 ends exactly where the single run did.
  const std::string checkpoint = test::tempPath("search.ckpt"), resumed = test::tempPath("resumed");
  ASSERT_EQ(run(common + "--method ga --population 10 --budget-evals 30 --checkpoint " +
                checkpoint + " --out " + resumed)
                .code,
            0);
  ASSERT_EQ(run(common + "--method ga --population 10 --budget-evals 60 --checkpoint " +
                checkpoint + " --out " + resumed)
                .code,
            0);
  const auto k = nlohmann::json::parse(readFile(resumed + "/search.json"));
  EXPECT_EQ(k["final_gc_error"], j["final_gc_error"]);
  EXPECT_EQ(k["evaluations"], j["evaluations"]);
  EXPECT_EQ(k["estimate"], j["estimate"]);
  // Settings that change the search itself must match.
  const Result refused =
      run(common + "--method ga --population 12 --budget-evals 60 --checkpoint " + checkpoint +
          " --out " + resumed);
  EXPECT_EQ(refused.code, 1);
  EXPECT_TRUE(contains(refused.err, "other settings")) << refused.err;
}
TEST(Cli, SearchStopsCleanlyOnInterrupt) {
  const std::string train = test::tempPath("int_train.csv"), dir = test::tempPath("interrupted");
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + train).code, 0);
  // SIGINT after 1.5 s of a 60 s budget: the best so far is written and the exit code is 130.
  const std::string command =
      std::string(DYNID_BIN) + " search --method nlo --robot puma560 --data " + train +
      " --perturb 0.3 --seed 1 --segments 20 --budget-seconds 60 " + "--out " + dir +
      " >/dev/null 2>&1 & pid=$!; sleep 1.5; kill -INT $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const auto j = nlohmann::json::parse(readFile(dir + "/search.json"));
  EXPECT_EQ(j["termination"], "interrupted");
  EXPECT_LT(j["seconds"].get<double>(), 30.0);
  EXPECT_GT(j["evaluations"].get<int>(), 0);
}
TEST(Cli, SearchAndExciteHoldTheirTimeBudgets) {
  // Wall time of the whole command, process start to exit: the budget covers the search (and,
  // for excite, the design's final evaluation, timed on the default sinusoid first).
  const std::string train = test::tempPath("budget_train.csv"),
                    held = test::tempPath("budget_held.csv");
  ASSERT_EQ(run("simulate --robot puma560 --duration 6 --out " + train).code, 0);
  ASSERT_EQ(run("simulate --robot puma560 --duration 6 --seed 2 --out " + held).code, 0);
  const auto timed = [](const std::string& command) {
    const auto start = std::chrono::steady_clock::now();
    const Result r = run(command);
    EXPECT_EQ(r.code, 0) << command << "\n" << r.err;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // Past the 3 s: one evaluation (a 100-segment PUMA GC error, ~0.02 s), the held-out GC error,
  // reading and writing (~0.1 s); 1 s of margin for a loaded 2-core machine. It ran 52 s for 30.
  const double search =
      timed("search --robot puma560 --method ga --perturb 0.3 --data " + train + " --validate " +
            held + " --budget-seconds 3 --out " + test::tempPath("budget_search"));
  EXPECT_LT(search, 3.0 + 1.0);
  EXPECT_GT(search, 2.5);  // it used its budget (the GA has no tolerance that ends it sooner)
  // excite's design is a PUMA Fourier motion; it ran 80 s for 60 before the final evaluation
  // counted. The same margin.
  const double excite =
      timed("excite --robot puma560 --budget-seconds 4 --out " + test::tempPath("budget_excite"));
  EXPECT_LT(excite, 4.0 + 1.0);
  EXPECT_GT(excite, 2.0);  // it used most of its budget (twice the final evaluation is reserved)
}
TEST(Cli, SearchUsageErrors) {
  EXPECT_EQ(run("search --method sgd --robot puma560 --data x.csv --out d").code, 2);
  EXPECT_EQ(run("search --method ga --robot puma560 --data x.csv --threads -1 --out d").code, 2);
  EXPECT_EQ(
      run("search --method ga --robot puma560 --data x.csv --init puma560 --perturb 0.1 --out d")
          .code,
      2);
  const Result missing = run("search --method ga --robot puma560 --data /nonexistent.csv --out d");
  EXPECT_EQ(missing.code, 1);
  EXPECT_TRUE(contains(missing.err, "/nonexistent.csv")) << missing.err;
}

}  // namespace
}  // namespace dynid
