// dynid simulate: the dataset, its summary line, and nothing left behind by a failed write.
#include <sys/wait.h>

#include <algorithm>
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

TEST(Cli, SimulateWritesADatasetAndSummary) {
  const std::string path = test::tempPath("sim.csv");
  const Result r =
      run("simulate --robot puma560 --duration 0.5 --noise-q 1e-4 --seed 3 --out " + path);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "501 samples x 6 joints")) << r.out;
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.substr(0, 8), "t,q1,q2,");
  // Same seed, same file; the Fourier controller runs too.
  const std::string again = test::tempPath("sim2.csv");
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 0.5 --noise-q 1e-4 --seed 3 --out " + again).code,
      0);
  EXPECT_EQ(readFile(path), readFile(again));
  EXPECT_EQ(
      run("simulate --robot puma560 --drives --controller fourier --duration 0.2 --out " + again)
          .code,
      0);
}
TEST(Cli, FailedWritesLeaveNoPartialFile) {
  const std::string dir = test::tempPath("no-such-dir");
  const Result r = run("simulate --robot puma560 --duration 0.1 --out " + dir + "/sim.csv");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, dir + "/sim.csv")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  const Result bad_rate =
      run("simulate --robot puma560 --dt 3e-4 --out " + test::tempPath("x.csv"));
  EXPECT_EQ(bad_rate.code, 1);
  EXPECT_TRUE(contains(bad_rate.err, "not a whole multiple")) << bad_rate.err;
}

}  // namespace
}  // namespace dynid
