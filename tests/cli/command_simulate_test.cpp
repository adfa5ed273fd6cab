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
  // The rows are formatted on --threads threads, in blocks of at most 512 kB of text (3 s: more
  // than 1 MB, so several blocks): the same bytes on one and on two.
  const std::string one = test::tempPath("sim_one.csv"), two = test::tempPath("sim_two.csv");
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --threads 1 --out " + one).code, 0);
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --threads 2 --out " + two).code, 0);
  EXPECT_GT(std::filesystem::file_size(one), std::size_t{1} << 20);
  EXPECT_EQ(readFile(one), readFile(two));
}
TEST(Cli, SimulateTracksADesignedExcitation) {
  const std::string design = test::tempPath("simulate_design");
  ASSERT_EQ(
      run("excite --robot puma560 --period 4 --segments 10 --starts 1 --evaluations 100 --out " +
          design)
          .code,
      0);
  const std::string csv = test::tempPath("simulate_design.csv");
  // Without --duration, one period of the design (not the default 10 s); with it, the design
  // repeats.
  ASSERT_EQ(run("simulate --robot puma560 --trajectory " + design +
                "/excitation.json --duration 6 --out " + csv)
                .code,
            0);
  EXPECT_EQ(readDatasetCsv(csv).numSamples(), 6001);
  const Result r =
      run("simulate --robot puma560 --trajectory " + design + "/excitation.json --out " + csv);
  ASSERT_EQ(r.code, 0) << r.err;
  const Trajectory t = readDatasetCsv(csv);
  ASSERT_EQ(t.numSamples(), 4001);
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
  EXPECT_FALSE(contains(r.err, "read as it is")) << r.err;  // a current design
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

namespace dynid {
namespace {

TEST(Cli, SimulatedPandaTracksWithoutChatterAndIdentifiesToItsNoiseFloor) {
  const std::string dir = test::tempPath("panda_chatter");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const std::string controller : {"sinusoidal", "fourier"}) {
    const std::string train = dir + "/train_" + controller + ".csv",
                      test = dir + "/test_" + controller + ".csv";
    const std::string common =
        "simulate --robot panda --drives --controller " + controller + " --noise-tau 0.05 ";
    const test::Result r = run(common + "--duration 12 --seed 1 --out " + train);
    ASSERT_EQ(r.code, 0) << r.err;
    // The mass-matrix diagonal's gains would chatter (torque jumping between +-87 N m): the
    // default switches to the effective inertias' and says so; no chatter warning.
    EXPECT_TRUE(contains(r.out, "note: default gains from the joints' effective inertias"))
        << r.out;
    // The library names the field; the CLI says the flag.
    EXPECT_TRUE(contains(r.out, "3x --bandwidth); not a fault")) << r.out;
    EXPECT_FALSE(contains(r.out, "warning:")) << r.out;
    ASSERT_EQ(run(common + "--duration 6 --seed 2 --out " + test).code, 0);
    // No torque step above 1 N m between 1 ms samples (0.13 N m measured; the chattering gains
    // gave 174 N m): the controller's torque is smooth, as a robot's.
    const Trajectory data = readDatasetCsv(train, 7);
    double step = 0.0;
    for (int k = 1; k < data.numSamples(); ++k)
      step = std::max(step, (data.tau.col(k) - data.tau.col(k - 1)).cwiseAbs().maxCoeff());
    EXPECT_LT(step, 1.0) << controller;
    // identify -> predict on simulate's own other trajectory: within 2 times the noise floor, the
    // relative error of the true model on the same noisy data (1.00 times measured).
    ASSERT_EQ(run("identify --method pc --robot panda --drives --data " + train + " --out " + dir +
                  "/est_" + controller)
                  .code,
              0);
    ASSERT_EQ(run("predict --estimate " + dir + "/est_" + controller + "/estimate.json --data " +
                  test + " --out " + dir + "/pred_" + controller)
                  .code,
              0);
    ASSERT_EQ(run("predict --robot panda --drives --data " + test + " --out " + dir + "/floor_" +
                  controller)
                  .code,
              0);
    const auto estimate =
        nlohmann::json::parse(readFile(dir + "/pred_" + controller + "/prediction.json"));
    const auto floor =
        nlohmann::json::parse(readFile(dir + "/floor_" + controller + "/prediction.json"));
    EXPECT_LT(estimate["relative_error"].get<double>(), 2.0 * floor["relative_error"].get<double>())
        << controller;
  }
}

// A design dynid excite wrote in version 1 (a fuzz seed since 2026-11-24) is tracked as it is,
// and simulate says so, as every reader of an older document does.
TEST(Cli, SimulateSaysWhenItReadsAnOlderDesign) {
  const std::string v1 =
      std::string(DYNID_SOURCE_DIR) + "/tests/fuzz/corpus/excitation_json/puma560_h2.json";
  const Result r = run("simulate --robot puma560 --trajectory " + v1 + " --duration 1 --out " +
                       test::tempPath("simulate_v1_design.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "is dynid.excitation version 1 (current 5): read as it is")) << r.err;
}

// --stiction: the paused arm's joints stop and stay at exactly zero velocity in its holds; without
// it Coulomb's sign(dq) chatters about zero and none does.
TEST(Cli, SimulateWithStictionHoldsTheArmAtRestInItsPauses) {
  const std::string stuck = test::tempPath("stiction.csv"), chatter = test::tempPath("law.csv");
  const std::string common =
      "simulate --robot puma560 --drives --duration 6 --amplitude 0.4 --pauses "
      "move=2,hold=1.5 --out ";
  ASSERT_EQ(run(common + stuck + " --stiction").code, 0);
  ASSERT_EQ(run(common + chatter).code, 0);
  const Trajectory held = readDatasetCsv(stuck, 6), law = readDatasetCsv(chatter, 6);
  for (int j = 0; j < 6; ++j) {
    // The holds (1.5 s from 2 s, 0.5 s from 5.5 s: 2000 samples at 1 kHz) and the moves' slow
    // ends and reversals that stick: 2278 to 2510 measured.
    EXPECT_GT((held.dq.row(j).array() == 0.0).count(), 2000) << "joint " << j + 1;
    EXPECT_LT((law.dq.row(j).array() == 0.0).count(), 10) << "joint " << j + 1;
  }
}

}  // namespace
}  // namespace dynid
