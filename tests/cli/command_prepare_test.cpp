// dynid prepare: raw logs into datasets, and the errors a user meets first.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/fixtures.hpp"
#include "tests/common/panda_log.hpp"
#include "tests/common/processes.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

/// One joint at 500 Hz in a whitespace table without a header: t, q [deg], tau.
std::string writeLog(const std::string& name, const std::string& bad_row = "") {
  std::ostringstream out;
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 2e-3;
    out << t << " " << 20.0 * std::sin(t) << " " << 3.0 * std::cos(t) << "\n";
    if (k == 10 && !bad_row.empty()) out << bad_row << "\n";
  }
  const std::string path = test::tempPath(name);
  writeFileAtomically(path, out.str());
  return path;
}

TEST(Cli, PrepareWritesADatasetAndItsRecord) {
  const std::string log = writeLog("one_joint.txt"), dir = test::tempPath("prepared");
  const Result r = run("prepare --log " + log + " --q 2 --tau 3 --angle-unit deg --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "1 runs at 500 Hz")) << r.out;
  const Trajectory d = readDatasetCsv(dir + "/train.csv", 1);
  // 0.2 s trimmed at each end of 4 s at 500 Hz.
  EXPECT_EQ(d.numSamples(), 2000 - 2 * 100);
  // q in radians now; ddq = -q for a sine of 1 rad/s (the filter and differences: ~1e-4).
  const double deg = 3.141592653589793 / 180.0;
  EXPECT_NEAR(d.q(0, 500), 20.0 * deg * std::sin(d.time[500]), 1e-6);
  EXPECT_NEAR(d.ddq(0, 500), -d.q(0, 500), 1e-4);
  const auto j = nlohmann::json::parse(readFile(dir + "/prepare.json"));
  EXPECT_EQ(j["schema_version"], 3);
  EXPECT_EQ(j["provenance"]["command"][1], "prepare");
  EXPECT_EQ(j["samples"]["train"], d.numSamples());
  EXPECT_EQ(j["filter"]["cutoff_hz"], 10.0);
  // The figures: the spectra with the cutoff, the torque before and after the filter.
  for (const char* figure : {"spectrum.svg", "filtered.svg"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + figure)) << figure;
  // --threads formats the rows (the same bytes for any count), in the range of every command's.
  const std::string one_dir = test::tempPath("prepared_one_thread");
  const Result one =
      run("prepare --log " + log + " --q 2 --tau 3 --angle-unit deg --threads 1 --out " + one_dir);
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_EQ(readFile(one_dir + "/train.csv"), readFile(dir + "/train.csv"));
  const Result too_many =
      run("prepare --log " + log + " --q 2 --tau 3 --threads 300 --out " + one_dir + "_x");
  EXPECT_EQ(too_many.code, 2) << too_many.err;
  EXPECT_TRUE(contains(too_many.err, "--threads")) << too_many.err;
  EXPECT_FALSE(std::filesystem::exists(one_dir + "_x"));
  // The cutoff from the spectrum, and Savitzky-Golay derivatives: said on the console and in
  // prepare.json.
  const std::string auto_dir = test::tempPath("prepared_auto");
  const Result a = run("prepare --log " + log +
                       " --q 2 --tau 3 --cutoff auto --derivative savgol --out " + auto_dir);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_TRUE(contains(a.out, "cutoff: auto: 99.5 % of q's power lies below")) << a.out;
  const auto ja = nlohmann::json::parse(readFile(auto_dir + "/prepare.json"));
  EXPECT_GT(ja["filter"]["trajectory_band_hz"].get<double>(), 0.0);
  EXPECT_EQ(ja["dq"].get<std::string>().rfind("Savitzky-Golay", 0), 0u) << ja["dq"];
}

TEST(Cli, APrepareRerunWithoutAHoldOutLeavesNoEarlierValidateCsv) {
  // The output set is replaced whole: the earlier run's validate.csv (of the earlier split) goes,
  // and another command's files in the same directory stay.
  const std::string log = writeLog("rerun.txt"), dir = test::tempPath("prepared_rerun");
  ASSERT_EQ(
      run("prepare --log " + log + " --q 2 --tau 3 --validate-fraction 0.3 --out " + dir).code, 0);
  ASSERT_TRUE(std::filesystem::exists(dir + "/validate.csv"));
  writeFileAtomically(dir + "/notes.txt", "mine");
  const Result again = run("prepare --log " + log + " --q 2 --tau 3 --out " + dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/validate.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/train.csv"));
  EXPECT_EQ(readFile(dir + "/notes.txt"), "mine");
}

TEST(Cli, PrepareNamesWhatIsWrongAndWritesNothing) {
  const std::string dir = test::tempPath("never_prepared");
  // A bad cell: the file, the line and the column.
  const std::string bad = writeLog("bad_cell.txt", "0.0205 1.0 oops");
  const Result cell = run("prepare --log " + bad + " --q 2 --tau 3 --out " + dir);
  EXPECT_EQ(cell.code, 1);
  EXPECT_TRUE(contains(cell.err, bad + ":12") && contains(cell.err, "'oops'")) << cell.err;
  const std::string log = writeLog("good.txt");
  // Usage errors: no source, no torque selector, a cutoff above Nyquist, an unknown unit.
  EXPECT_EQ(run("prepare --out " + dir).code, 2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --out " + dir).code, 2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --time-unit min --out " + dir).code, 2);
  const Result nyquist = run("prepare --log " + log + " --q 2 --tau 3 --cutoff 300 --out " + dir);
  EXPECT_EQ(nyquist.code, 1);
  EXPECT_TRUE(contains(nyquist.err, "Nyquist")) << nyquist.err;
  // A selector that matches nothing names the columns there are.
  const Result column = run("prepare --log " + log + " --q 2 --tau 7 --out " + dir);
  EXPECT_EQ(column.code, 1);
  EXPECT_TRUE(contains(column.err, "out of range")) << column.err;
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --cutoff fast --out " + dir).code, 2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --cutoff -1 --out " + dir).code, 2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --derivative spline --out " + dir).code,
            2);
  // Currents: torque constants required (exit 2), and they only apply to currents.
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --current 3 --out " + dir).code, 2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --torque-constants 0.1 --out " + dir).code,
            2);
  EXPECT_EQ(run("prepare --log " + log + " --q 2 --tau 3 --current 3 --out " + dir).code, 2);
  const Result count =
      run("prepare --log " + log + " --q 2 --current 3 --torque-constants 0.1,0.2 --out " + dir);
  EXPECT_EQ(count.code, 1);
  EXPECT_TRUE(contains(count.err, "--torque-constants has 2 values") &&
              contains(count.err, "has 1 joints"))
      << count.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
}

TEST(Cli, PrepareConvertsCurrentsAndJoinsNoFiles) {
  const std::string a = writeLog("amps_a.txt"), b = writeLog("amps_b.txt");
  const std::string dir = test::tempPath("from_currents");
  const Result r = run("prepare --log " + a + " " + b +
                       " --q 2 --current 3 --torque-constants 0.5 --gear-ratios 100 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Trajectory d = readDatasetCsv(dir + "/train.csv", 1);
  // 3 cos(t) A x 0.5 N m/A x 100, through the 10 Hz filter (~1e-5 of a 1 rad/s cosine).
  EXPECT_NEAR(d.tau(0, 500), 150.0 * std::cos(d.time[500]), 1e-2);
  const auto j = nlohmann::json::parse(readFile(dir + "/prepare.json"));
  EXPECT_EQ(j["source"]["tables"].size(), 2u);
  EXPECT_EQ(j["source"]["current_to_torque"]["gear_ratios"][0], 100.0);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_EQ(j["runs"][1]["file"], 1);
  EXPECT_GT(j["runs"][1]["time_offset"].get<double>(), 4.0);
  // The second file held out whole; time ranges parse as from:to pairs.
  const std::string held = test::tempPath("held_run");
  ASSERT_EQ(run("prepare --log " + a + " " + b +
                " --q 2 --tau 3 --validate-runs 2 --validate-time 1:1.5 --out " + held)
                .code,
            0);
  const auto jh = nlohmann::json::parse(readFile(held + "/prepare.json"));
  EXPECT_EQ(jh["held_out"]["runs"], nlohmann::json::array({2}));
  EXPECT_EQ(jh["held_out"]["time_ranges"][0][1], 1.5);
  EXPECT_EQ(run("prepare --log " + a + " --q 2 --tau 3 --validate-time 2:1 --out " + held).code, 2);
  EXPECT_EQ(run("prepare --log " + a + " --q 2 --tau 3 --validate-runs 0 --out " + held).code, 2);
  EXPECT_EQ(run("prepare --log " + a + " --q 2 --tau 3 --validate-runs 5 --out " + held).code, 1);
}

// The joints' columns in the file's reverse order and a second of rest first: prepare takes the
// joints by the numbers in the names and says which column went where, warns of the rest with the
// window that crops it, and keeps that window when given.
TEST(Cli, PrepareRecordsTheJointColumnsWarnsOfRestAndKeepsAWindow) {
  std::ostringstream out;
  out.precision(17);
  out << "t,q2,q1,tau2,tau1\n";
  for (int k = 0; k <= 2500; ++k) {
    const double t = k * 2e-3, s = std::max(t - 1.0, 0.0);  // at rest for the first second
    const double q1 = 0.5 * (1.0 - std::cos(2.0 * s)), q2 = -0.3 * (1.0 - std::cos(3.0 * s));
    out << t << "," << q2 << "," << q1 << "," << 2.0 * q2 << "," << q1 << "\n";
  }
  const std::string log = test::tempPath("reversed.csv"), dir = test::tempPath("reversed");
  writeFileAtomically(log, out.str());
  const std::string common = "prepare --log " + log + " --time t --q 'q*' --tau 'tau*' ";
  const Result r = run(common + "--out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "1: q1, tau1, 2: q2, tau2")) << r.out;
  EXPECT_TRUE(contains(r.err, "warning: ") && contains(r.err, "at rest") &&
              contains(r.err, "--window 1."))
      << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/prepare.json"));
  EXPECT_EQ(j["columns"][0]["q"], (std::vector<std::string>{"q1", "q2"}));
  EXPECT_EQ(j["columns"][0]["tau"], (std::vector<std::string>{"tau1", "tau2"}));
  EXPECT_EQ(j["warnings"].size(), 1u);
  const Trajectory d = readDatasetCsv(dir + "/train.csv", 2);
  EXPECT_NEAR(d.tau(1, 1000), 2.0 * d.q(1, 1000), 1e-9);  // joint 2's torque is twice its q
  // The window crops the rest: no warning, and recorded.
  const std::string windowed = test::tempPath("windowed");
  const Result w = run(common + "--window 1:5 --out " + windowed);
  ASSERT_EQ(w.code, 0) << w.err;
  EXPECT_FALSE(contains(w.err, "warning")) << w.err;
  const auto jw = nlohmann::json::parse(readFile(windowed + "/prepare.json"));
  EXPECT_EQ(jw["windows"]["time"], nlohmann::json::parse("[[1, 5]]"));
  // The robot's joint count is checked; its limits bound the speed (3 x the Panda's 2.175 rad/s
  // for joint 1 is far above this motion), and a bound below the motion is refused.
  const Result robot = run(common + "--robot panda --out " + test::tempPath("never_robot"));
  EXPECT_EQ(robot.code, 1);
  EXPECT_TRUE(contains(robot.err, "expected 7")) << robot.err;
  const Result slow = run(common + "--dq-max 0.2 --out " + test::tempPath("never_slow"));
  EXPECT_EQ(slow.code, 1);
  EXPECT_TRUE(contains(slow.err, "joint 1") && contains(slow.err, "--dq-max")) << slow.err;
  for (const char* bad : {"--window 5:1", "--window 1", "--rows 0:10", "--rows 2.5:10"})
    EXPECT_EQ(run(common + bad + " --out " + test::tempPath("never_bad")).code, 2) << bad;
}

// A ROS 1 bag (written by ROS's own writer) prepared from the command line: its joints as the
// messages name them, or the robot's matched by name; table options refused.
TEST(Cli, PrepareReadsARos1BagAndRefusesTableOptionsForIt) {
  const std::string bag = (test::bagFixtures() / "joint_states_lz4.bag").string();
  const std::string dir = test::tempPath("from_bag");
  const Result r = run("prepare --log " + bag + " --cutoff 0 --trim 0 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "1: joint2, joint2, 2: joint1, joint1, 3: gripper, gripper"))
      << r.out;
  EXPECT_EQ(readDatasetCsv(dir + "/train.csv", 3).numSamples(), 200);
  const auto j = nlohmann::json::parse(readFile(dir + "/prepare.json"));
  EXPECT_EQ(j["columns"][0]["time"], "header.stamp");
  EXPECT_EQ(j["time_origin"]["exact"], "1700000000");
  const Result robot = run("prepare --log " + bag + " --robot puma560 --cutoff 0 --trim 0 --out " +
                           test::tempPath("never_bag"));
  EXPECT_EQ(robot.code, 1);
  EXPECT_TRUE(contains(robot.err, "lack the robot's joints joint3") && contains(robot.err, bag))
      << robot.err;
  // --joint-names: the messages' names for the joints, in the robot's order (a driver that names
  // them otherwise); one per joint of --robot.
  const std::string named = test::tempPath("bag_named");
  const Result names = run("prepare --log " + bag +
                           " --joint-names joint1,gripper --cutoff 0 --trim 0 --out " + named);
  ASSERT_EQ(names.code, 0) << names.err;
  EXPECT_TRUE(contains(names.out, "1: joint1, joint1, 2: gripper, gripper")) << names.out;
  const Trajectory by_name = readDatasetCsv(named + "/train.csv", 2);
  const Trajectory all = readDatasetCsv(dir + "/train.csv", 3);
  EXPECT_EQ(by_name.q.row(0), all.q.row(1));  // joint1, the messages' second
  const Result count = run("prepare --log " + bag + " --robot puma560 --joint-names joint1,joint2" +
                           " --out " + test::tempPath("never_named"));
  EXPECT_EQ(count.code, 2);
  EXPECT_TRUE(contains(count.err, "--joint-names gives 2 names, the robot has 6")) << count.err;
  const std::string never = " --out " + test::tempPath("never_bag");
  for (const std::string& bad :
       {"--log " + bag + " --q 'q*'", "--log " + bag + " --time-unit ms",
        "--log " + bag + " " + writeLog("beside_bag.txt") + " --q 2 --tau 3",
        "--log " + bag + " --stamp sideways",
        "--log " + writeLog("t.txt") +
            " --q 2 --tau 3 "
            "--stamp receive",
        "--log " + writeLog("t2.txt") + " --q 2 --tau 3 --topic /js",
        "--log " + writeLog("t3.txt") + " --q 2 --tau 3 --joint-names a,b",
        "--log " + bag + " --joint-names joint1,joint1"})
    EXPECT_EQ(run("prepare " + bad + never).code, 2) << bad;
}

// ROS 2 recordings from the MCAP project's writer and SQLite (tools/mcap/joint_states.mjs): every
// container (zstd, lz4 and unchunked MCAP, a .db3, a split bag directory) gives the same dataset,
// byte for byte, and the ROS 1 bag of the same values gives it to the last bits of sin and cos
// (JavaScript's and glibc's may differ by one ulp); --stamp receive counts from the receive time.
TEST(Cli, EveryRos2ContainerPreparesTheSameDatasetAsTheRos1Bag) {
  const std::string fixtures = test::bagFixtures().string() + "/";
  const auto prepare = [&](const std::string& log, const std::string& extra) {
    const std::string dir = test::tempPath("ros2_prepared");
    const Result r =
        run("prepare --log " + log + " --cutoff 0 --trim 0 " + extra + " --out " + dir);
    EXPECT_EQ(r.code, 0) << log << "\n" << r.err;
    return dir;
  };
  const std::string ros1 = prepare(fixtures + "joint_states_lz4.bag", "");
  const Trajectory reference = readDatasetCsv(ros1 + "/train.csv", 3);
  const std::string first =
      readFile(prepare(fixtures + "ros2/joint_states.db3", "") + "/train.csv");
  for (const char* name : {"joint_states_zstd.mcap", "joint_states_lz4.mcap",
                           "joint_states_plain.mcap", "joint_states_split"}) {
    const std::string dir = prepare(fixtures + "ros2/" + name, "");
    EXPECT_EQ(readFile(dir + "/train.csv"), first) << name;
  }
  const std::string path = test::tempPath("ros2_first.csv");
  writeFileAtomically(path, first);
  const Trajectory ros2 = readDatasetCsv(path, 3);
  ASSERT_EQ(ros2.numSamples(), reference.numSamples());
  // One ulp of sin's 0.3 amplitude, differentiated over 1 ms steps: well under 1e-12.
  EXPECT_LT((ros2.q - reference.q).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((ros2.dq - reference.dq).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(ros2.tau, reference.tau);
  const std::string receive = prepare(fixtures + "ros2/joint_states_split", "--stamp receive");
  const auto j = nlohmann::json::parse(readFile(receive + "/prepare.json"));
  EXPECT_EQ(j["time_origin"]["exact"], "1700000000.00025");
}

// A recording whose JointState messages carry no effort: the efforts of a second topic (every
// 2 ms, between the position stamps, joints in another order) or of a table (epoch seconds)
// interpolated at the position stamps. The fixture's efforts are linear in time, so the
// interpolation gives the same dataset as the recording that carries them.
TEST(Cli, EffortsComeFromASecondTopicOrATableAtThePositionStamps) {
  const std::string fixtures = (test::bagFixtures() / "ros2").string() + "/";
  const std::string rec = fixtures + "joint_states_effort_topic.mcap";
  const auto prepare = [&](const std::string& args) {
    const std::string dir = test::tempPath("effort_prepared");
    const Result r = run("prepare " + args + " --cutoff 0 --trim 0 --out " + dir);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    return dir;
  };
  const std::string reference =
      readFile(prepare("--log " + fixtures + "joint_states_zstd.mcap") + "/train.csv");
  const std::string topic =
      prepare("--log " + rec + " --topic /joint_states --effort-topic /joint_efforts");
  EXPECT_EQ(readFile(topic + "/train.csv"), reference);
  EXPECT_EQ(nlohmann::json::parse(readFile(topic + "/prepare.json"))["source"]["effort_topic"],
            "/joint_efforts");
  // A table of the same efforts at 500 Hz in epoch seconds (columns in the joint order), ending
  // at 197.5 ms:
  // the position samples at 198 and 199 ms lie outside it, are dropped, and that is said.
  const std::string csv = test::tempPath("efforts.csv");
  std::ostringstream fixed;
  fixed.precision(17);
  fixed << "stamp,effort_joint2,effort_joint1,effort_gripper\n";
  for (int i = 0; i < 100; ++i) {
    const long long ns = 1700000000LL * 1000000000 - 500000 + 2000000LL * i;  // -0.5 ms, 1.5 ms
    const double ms = static_cast<double>(ns - 1700000000LL * 1000000000) * 1e-6;
    fixed << ns / 1000000000 << "." << std::setw(9) << std::setfill('0') << ns % 1000000000
          << std::setfill(' ');
    for (int n : {2, 1, 3}) fixed << "," << 2.0 * n + 0.5 * ms;
    fixed << "\n";
  }
  writeFileAtomically(csv, fixed.str());
  const std::string dir = test::tempPath("effort_table");
  const Result from_table =
      run("prepare --log " + rec + " --topic /joint_states --effort-log " + csv +
          " --time stamp --tau effort_joint2,effort_joint1,effort_gripper --cutoff 0 "
          "--trim 0 --out " +
          dir);
  ASSERT_EQ(from_table.code, 0) << from_table.err;
  EXPECT_TRUE(contains(from_table.err, "position samples outside the efforts' time span"))
      << from_table.err;
  const Trajectory got = readDatasetCsv(dir + "/train.csv", 3);
  const std::string path = test::tempPath("effort_reference.csv");
  writeFileAtomically(path, reference);
  const Trajectory want = readDatasetCsv(path, 3);
  ASSERT_EQ(got.numSamples(), want.numSamples() - 2);
  // Stamps read as decimal seconds: their ns are exact, the weights to the double's precision.
  EXPECT_LT((got.tau - want.tau.leftCols(got.numSamples())).cwiseAbs().maxCoeff(), 1e-12);
  // Usage: one effort source, for recordings only, and --tau with it.
  const std::string never = " --out " + test::tempPath("never_effort");
  for (const std::string& bad :
       {"--log " + rec + " --effort-topic /a --effort-log " + csv + " --tau x",
        "--log " + rec + " --effort-log " + csv, "--log " + rec + " --tau x",
        "--log " + writeLog("effort_t.txt") + " --q 2 --tau 3 --effort-topic /a"})
    EXPECT_EQ(run("prepare " + bad + never).code, 2) << bad;
}

// The held-out raw torques: prepare --keep-raw-torque writes them at the log's own stamps, and
// identify --validate-raw and predict --raw report the error against them beside the error
// against the filtered held-out dataset (the same numbers in both commands).
TEST(Cli, IdentifyAndPredictReportTheErrorAgainstTheRawHeldOutTorque) {
  const std::string dir = test::tempPath("raw_torque"), log = test::tempPath("raw_torque.csv");
  ASSERT_EQ(run("simulate --robot puma560 --duration 4 --noise-tau 0.05 --out " + log).code, 0);
  const Result prepared = run("prepare --log " + log +
                              " --q 'q*' --tau 'tau*' "
                              "--validate-fraction 0.25 --keep-raw-torque --out " +
                              dir + "/data");
  ASSERT_EQ(prepared.code, 0) << prepared.err;
  EXPECT_TRUE(contains(prepared.out, "validate_raw.csv")) << prepared.out;
  const Result identified = run(
      "identify --robot puma560 --data " + dir + "/data/train.csv --validate " + dir +
      "/data/validate.csv --validate-raw " + dir + "/data/validate_raw.csv --out " + dir + "/ols");
  ASSERT_EQ(identified.code, 0) << identified.err;
  const auto at = identified.out.find("against the raw torque at its ");
  ASSERT_NE(at, std::string::npos) << identified.out;
  const std::string line = identified.out.substr(at, identified.out.find('\n', at) - at);
  const auto estimate = nlohmann::json::parse(readFile(dir + "/ols/estimate.json"));
  const auto& raw = estimate["validation"]["raw_measurement"];
  EXPECT_GT(raw["samples"].get<int>(), 500);
  // The raw torque carries the simulated noise the filtered one does not: a larger error.
  EXPECT_GT(raw["relative_error"].get<double>(),
            estimate["validation"]["relative_error"].get<double>());
  const Result predicted =
      run("predict --estimate " + dir + "/ols/estimate.json --data " + dir +
          "/data/validate.csv --raw " + dir + "/data/validate_raw.csv --out " + dir + "/pred");
  ASSERT_EQ(predicted.code, 0) << predicted.err;
  EXPECT_TRUE(contains(predicted.out, line)) << predicted.out << "\n" << line;
  EXPECT_EQ(nlohmann::json::parse(
                readFile(dir + "/pred/prediction.json"))["raw_measurement"]["relative_error"],
            raw["relative_error"]);
  const std::string never = " --out " + test::tempPath("never_raw");
  EXPECT_EQ(run("prepare --log " + log + " --q 'q*' --tau 'tau*' --keep-raw-torque" + never).code,
            2);
  EXPECT_EQ(run("identify --robot puma560 --data " + dir + "/data/train.csv --validate-raw " + dir +
                "/data/validate_raw.csv" + never)
                .code,
            2);
  EXPECT_EQ(run("predict --estimate " + dir + "/ols/estimate.json --data " + dir +
                "/data/validate.csv --raw " + dir + "/data/validate.csv" + never)
                .code,
            1);
}

// Gaz et al.'s real Panda log as a ROS 1 bag written by ROS's own writer
// (tools/panda_log_as_ros1_bag.py: joints published out of the robot's order, a finger joint
// beside them), prepared and identified with examples/panda/run.sh's options: the example's
// numbers (docs: OLS 0.9142 % on the training part, 0.9393 % held out).
TEST(Cli, ThePandaLogAsARos1BagGivesTheExamplesNumbers) {
  const std::string log = test::pandaLogDirectory();
  if (log.empty()) GTEST_SKIP() << "the Panda log is not beside the repository";
  // Started without a shell: the paths go to the interpreter as arguments.
  if (test::runProgram({"/usr/bin/python3", "-c", "import rosbag"}) != 0)
    GTEST_SKIP() << "python3-rosbag is not installed (scripts/install-deps.sh installs it)";
  const std::string bag = test::tempPath("panda.bag"), dir = test::tempPath("panda_bag");
  ASSERT_EQ(test::runProgram({"/usr/bin/python3",
                              std::string(DYNID_SOURCE_DIR) + "/tools/panda_log_as_ros1_bag.py",
                              log, bag}),
            0);
  const Result prepared = run("prepare --log " + bag +
                              " --robot panda --rate 1000 --cutoff 5 --max-gap 0.02 "
                              "--validate-fraction 0.2 --out " +
                              dir + "/data");
  ASSERT_EQ(prepared.code, 0) << prepared.err;
  const Result ols =
      run("identify --method ols --robot panda --drive-terms fv,fc,fo --data " + dir +
          "/data/train.csv --validate " + dir + "/data/validate.csv --out " + dir + "/ols");
  ASSERT_EQ(ols.code, 0) << ols.err;
  EXPECT_TRUE(contains(ols.out, "relative torque error 0.9142 %")) << ols.out;
  EXPECT_TRUE(contains(ols.out, "held out: relative torque error 0.9393 %")) << ols.out;
}

}  // namespace
}  // namespace dynid
