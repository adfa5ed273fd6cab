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
TEST(Cli, SimulateTracksADesignedExcitation) {
  const std::string design = test::tempPath("simulate_design");
  ASSERT_EQ(
      run("excite --robot puma560 --segments 10 --starts 1 --evaluations 100 --out " + design).code,
      0);
  const std::string csv = test::tempPath("simulate_design.csv");
  const Result r =
      run("simulate --robot puma560 --trajectory " + design + "/excitation.json --out " + csv);
  ASSERT_EQ(r.code, 0) << r.err;
  const Trajectory t = readDatasetCsv(csv);
  ASSERT_EQ(t.numSamples(), 10001);
  // The design starts at rest, and the simulation starts on it: no start-up transient.
  EXPECT_LT(t.dq.col(0).cwiseAbs().maxCoeff(), 1e-12);
  // Tracking it at 5 Hz bandwidth: within a few hundredths of a radian.
  const auto j = nlohmann::json::parse(readFile(design + "/excitation.json"));
  // ... at the design's q(0) = offset - sum_k b_k / (w k).
  const double w = 2.0 * 3.14159265358979323846 / j["design"]["period"].get<double>();
  for (int joint = 0; joint < 6; ++joint) {
    double q0 = j["design"]["offset"][joint].get<double>();
    for (int k = 0; k < 5; ++k) q0 -= j["design"]["b"][joint][k].get<double>() / (w * (k + 1));
    EXPECT_NEAR(t.q(joint, 0), q0, 1e-12) << joint;  // round-off of a short sum
  }
  EXPECT_TRUE(contains(r.out, "tracking error RMS")) << r.out;
  // --trajectory replaces the controller and its amplitude; a file that is not a design fails.
  EXPECT_EQ(run("simulate --robot puma560 --trajectory " + design +
                "/excitation.json --controller fourier --out " + csv)
                .code,
            2);
  const Result bad = run("simulate --robot puma560 --trajectory " + csv + " --out " + csv + "2");
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(contains(bad.err, csv)) << bad.err;
  const Result panda = run("simulate --robot panda --trajectory " + design +
                           "/excitation.json --out " + csv + "3");  // a 6-joint design
  EXPECT_EQ(panda.code, 1);
  EXPECT_TRUE(contains(panda.err, "design.offset")) << panda.err;
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
