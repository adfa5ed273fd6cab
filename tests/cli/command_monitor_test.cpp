// dynid monitor through the executable: a simulated push found against the ground truth, the
// thresholds read back, samples streamed on stdin with events as JSON lines, Ctrl-C while waiting.
#include <sys/wait.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/joint_state_db3.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

class CliMonitor : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::tempPath("cli_monitor");
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    ASSERT_EQ(run("simulate --robot puma560 --duration 8 --noise-tau 0.05 --noise-dq 0.001 "
                  "--seed 1 --out " +
                  dir_ + "/clean.csv")
                  .code,
              0);
    const Result pushed =
        run("simulate --robot puma560 --duration 6 --noise-tau 0.05 --noise-dq 0.001 --seed 2 "
            "--disturbance joint=joint2,torque=10,at=2,for=0.2 "
            "--disturbance link=6,force=0:0:-40,at=4,for=0.15 --out " +
            dir_ + "/pushed.csv");
    ASSERT_EQ(pushed.code, 0) << pushed.err;
    ASSERT_TRUE(contains(pushed.out, "pushed.truth.csv")) << pushed.out;
  }
  static std::string dir_;
};
std::string CliMonitor::dir_;

TEST_F(CliMonitor, FindsThePushesAndReadsItsThresholdsBack) {
  const std::string out = dir_ + "/m";
  const Result r = run("monitor --arm puma560 --data " + dir_ + "/pushed.csv --calibration " +
                       dir_ + "/clean.csv --truth " + dir_ + "/pushed.truth.csv --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "2 of 2 disturbances detected within 50 ms, 0 false alarm(s)"))
      << r.out;
  const auto j = nlohmann::json::parse(readFile(out + "/monitor.json"));
  EXPECT_EQ(j["kind"], "dynid.monitor");
  ASSERT_EQ(j["events"].size(), 2u);
  EXPECT_EQ(j["events"][0]["joints"], nlohmann::json::array({2}));
  // Contact isolation: a push at joint 2 is on link 2 or beyond; the force on link 6 shows on
  // joints up to its own, never beyond.
  EXPECT_EQ(j["events"][0]["contact_link"], 2);
  // Why the thresholds are where they are: 8 s of calibration confirm no rate below 1350 per
  // hour; the default 0.1 per hour would need 30 h.
  EXPECT_EQ(j["calibration_confidence"]["confirmed_false_alarms_per_hour"], 1350.0);
  EXPECT_TRUE(j["calibration_confidence"]["extrapolated"].get<bool>());
  EXPECT_TRUE(contains(r.out, "0.1 per hour would need 30 h of clean calibration")) << r.out;
  EXPECT_LE(j["events"][1]["contact_link"].get<int>(), 6);
  EXPECT_EQ(j["events"][1]["contact_link"], j["events"][1]["joints"].back());
  EXPECT_GE(j["events"][0]["start"].get<double>(), 2.0);
  EXPECT_LT(j["events"][0]["start"].get<double>(), 2.05);
  for (const char* file : {"thresholds.json", "report.md", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  const std::string html = readFile(out + "/report.html");
  EXPECT_TRUE(test::opensWithVerdict(
      html, {"Watched", "Found", "Thresholds", "Against the truth", "Next"}));
  EXPECT_TRUE(contains(html, "2 events on joints 2, 3")) << html.substr(0, 2000);
  // The saved thresholds give the same events.
  const Result again = run("monitor --arm puma560 --data " + dir_ + "/pushed.csv --thresholds " +
                           out + "/thresholds.json --out " + dir_ + "/m2");
  ASSERT_EQ(again.code, 0) << again.err;
  const auto k = nlohmann::json::parse(readFile(dir_ + "/m2/monitor.json"));
  EXPECT_EQ(k["events"], j["events"]);
  EXPECT_EQ(k["thresholds"]["thresholds"], j["thresholds"]["thresholds"]);
}

TEST_F(CliMonitor, SaysHowARestingArmIsJudgedAndKeepsItsThresholdsAtRest) {
  // Without stops the calibration has no thresholds at rest, and says what would give them.
  const Result plain = run("monitor --arm puma560 --data " + dir_ + "/pushed.csv --calibration " +
                           dir_ + "/clean.csv --out " + dir_ + "/plain");
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_TRUE(contains(plain.out, "The calibration held its pose 0 s (2 s are needed)"))
      << plain.out;
  // With stops (simulate --pauses): thresholds at rest, why, and the same after a read-back.
  ASSERT_EQ(run("simulate --robot puma560 --duration 12 --noise-tau 0.05 --noise-dq 0.001 "
                "--seed 3 --pauses move=2,hold=2.5 --out " +
                dir_ + "/stops.csv")
                .code,
            0);
  const std::string out = dir_ + "/rest";
  const Result r = run("monitor --arm puma560 --data " + dir_ + "/stops.csv --calibration " + dir_ +
                       "/stops.csv --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "0 events")) << r.out;  // a clean run raises no alarm
  EXPECT_TRUE(contains(r.out, "judged by thresholds at rest learnt from the calibration's"))
      << r.out;
  // 12 s of calibration are too few for thresholds per moving regime (10 s each), and it says so.
  EXPECT_TRUE(contains(r.out, "which none of its 36 did: the single moving threshold applies"))
      << r.out;
  const auto j = nlohmann::json::parse(readFile(out + "/thresholds.json"));
  EXPECT_EQ(j["schema_version"], 5);
  EXPECT_EQ(j["provenance"]["command"][1], "monitor");
  EXPECT_EQ(j["model_source"]["spec"], "puma560");  // the arm they were set for, embedded
  EXPECT_EQ(j["model"]["name"], "puma560");
  ASSERT_EQ(j["thresholds_at_rest"].size(), 6u);
  ASSERT_EQ(j["moving_regimes"]["thresholds"].size(), 6u);
  EXPECT_EQ(j["moving_regimes"]["thresholds"][0][0], nullptr);
  const Result again = run("monitor --arm puma560 --data " + dir_ + "/stops.csv --thresholds " +
                           out + "/thresholds.json --out " + dir_ + "/rest2");
  ASSERT_EQ(again.code, 0) << again.err;
  const auto k = nlohmann::json::parse(readFile(dir_ + "/rest2/monitor.json"));
  EXPECT_EQ(k["thresholds"]["thresholds_at_rest"], j["thresholds_at_rest"]);
  EXPECT_EQ(k["thresholds"]["moving_regimes"], j["moving_regimes"]);
  EXPECT_EQ(k["events"].size(), 0u);
}

// The pushed log as a ROS 2 recording (JointState with velocities, as a driver publishes them):
// the same pushes found, at the recording's own stamps; its options refused on a dataset.
TEST_F(CliMonitor, WatchesARecording) {
  const Trajectory pushed = readDatasetCsv(dir_ + "/pushed.csv");
  const std::string bag = dir_ + "/pushed.db3";
  {
    test::JointStateDb3 db3(bag, {"/robot/joint_states"});
    const std::vector<std::string> names{"joint1", "joint2", "joint3",
                                         "joint4", "joint5", "joint6"};
    for (int k = 0; k < pushed.numSamples(); ++k) {
      const Eigen::VectorXd q = pushed.q.col(k), dq = pushed.dq.col(k), tau = pushed.tau.col(k);
      const std::int64_t ns = 1700000000000000000LL + std::llround(pushed.time[k] * 1e9);
      db3.add(ns, ns + 200000, names, q.data(), dq.data(), tau.data());
    }
    db3.close();
  }
  const Result r = run("monitor --arm puma560 --data " + bag + " --calibration " + dir_ +
                       "/clean.csv --truth " + dir_ + "/pushed.truth.csv --out " + dir_ + "/mb");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "2 of 2 disturbances detected within 50 ms, 0 false alarm(s)"))
      << r.out;
  const Result csv = run("monitor --arm puma560 --data " + dir_ + "/pushed.csv --calibration " +
                         dir_ + "/clean.csv --topic /robot/joint_states --out " + dir_ + "/mt");
  EXPECT_EQ(csv.code, 2);
  EXPECT_TRUE(contains(csv.err, "--topic applies to recordings")) << csv.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/mt"));
  // A recording without velocities: the command line it suggests is the CLI's (the library
  // names prepare's fields; Python's message names them as keyword arguments).
  const std::string still = dir_ + "/no_velocity.db3";
  {
    test::JointStateDb3 db3(still, {"/joint_states"});
    const std::vector<std::string> names{"joint1", "joint2", "joint3",
                                         "joint4", "joint5", "joint6"};
    for (int k = 0; k < 100; ++k) {
      const Eigen::VectorXd q = pushed.q.col(k), tau = pushed.tau.col(k);
      const std::int64_t ns = 1700000000000000000LL + std::llround(pushed.time[k] * 1e9);
      db3.add(ns, ns, names, q.data(), nullptr, tau.data());
    }
    db3.close();
  }
  const Result none = run("monitor --arm puma560 --data " + still + " --calibration " + dir_ +
                          "/clean.csv --out " + dir_ + "/mv");
  EXPECT_EQ(none.code, 1);
  EXPECT_TRUE(contains(none.err, "(dynid prepare --log " + still + " --robot ROBOT --out DIR)"))
      << none.err;
  EXPECT_FALSE(contains(none.err, "`")) << none.err;
}

TEST_F(CliMonitor, StreamedOnStdinItPrintsEachEventAsItHappens) {
  const Result r = run("monitor --arm puma560 --data - --calibration " + dir_ + "/clean.csv < " +
                       dir_ + "/pushed.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::vector<nlohmann::json> events;
  while (std::getline(lines, line)) events.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(events.size(), 4u) << r.out;  // two starts, two ends
  EXPECT_EQ(events[0]["event"], "start");
  EXPECT_EQ(events[1]["event"], "end");
  EXPECT_EQ(events[0]["start"], events[1]["start"]);
  EXPECT_TRUE(contains(r.err, "2 events")) << r.err;
  // A simulation piped straight into it, without a ground-truth file: the same two pushes.
  const Result piped =
      run("simulate --robot puma560 --duration 6 --noise-tau 0.05 --noise-dq 0.001 --seed 2 "
          "--disturbance joint=joint2,torque=10,at=2,for=0.2 "
          "--disturbance link=6,force=0:0:-40,at=4,for=0.15 --out - 2>/dev/null | " +
          std::string(DYNID_BIN) + " monitor --arm puma560 --data - --calibration " + dir_ +
          "/clean.csv");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.out, r.out);  // the same samples, so the same event lines
  // A stream cut in the middle of a line is an error naming it.
  const std::string whole = readFile(dir_ + "/pushed.csv");
  ASSERT_NE(whole[99999], '\n');
  std::ofstream(dir_ + "/cut.csv", std::ios::binary) << whole.substr(0, 100000);
  const Result cut = run("monitor --arm puma560 --data - --calibration " + dir_ + "/clean.csv < " +
                         dir_ + "/cut.csv");
  EXPECT_EQ(cut.code, 1);
  EXPECT_TRUE(contains(cut.err, "<stdin>")) << cut.err;
  EXPECT_TRUE(contains(cut.err, "middle of a line")) << cut.err;
}

TEST_F(CliMonitor, CtrlCWhileWaitingForSamplesEndsWithTheEventsSoFar) {
  // 2500 of the 6001 rows, then the writer keeps the pipe open: monitor waits for more when
  // SIGINT comes, sent once the first push (at 2 s) has been printed (however long the
  // calibration took). It ends cleanly (exit 130) with that event.
  const std::string script =
      "cd " + dir_ + " && rm -f pipe && mkfifo pipe && " +
      "{ (head -n 2500 pushed.csv; exec sleep 60) > pipe & writer=$!; " + DYNID_BIN +
      " monitor --arm puma560 --data - --calibration clean.csv --out live < pipe > live.jsonl "
      "2> live.err & pid=$!; "
      "for i in $(seq 1200); do grep -q start live.jsonl && break; sleep 0.1; done; "
      "kill -INT $pid; wait $pid; code=$?; kill $writer; exit $code; }";
  std::filesystem::remove_all(dir_ + "/live");
  const int status = std::system(("bash -c '" + script + "'").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 130) << readFile(dir_ + "/live.err");
  EXPECT_TRUE(contains(readFile(dir_ + "/live.err"), "interrupted (Ctrl-C)"));
  const std::string printed = readFile(dir_ + "/live.jsonl");
  EXPECT_TRUE(contains(printed, "\"event\":\"start\"")) << printed;
  const auto j = nlohmann::json::parse(readFile(dir_ + "/live/monitor.json"));
  EXPECT_TRUE(j["interrupted"].get<bool>());
  EXPECT_EQ(j["events"].size(), 1u);
  // Every sample up to the push's at least, at most the 2499 sent: SIGINT follows the printed
  // event by up to 0.1 s, and on a loaded machine (the sanitizer suite on 2 busy cores) the
  // monitor may not yet have read the rest of what was sent by then.
  EXPECT_GE(j["samples"].get<int>(), 2000);
  EXPECT_LE(j["samples"].get<int>(), 2499);
}

TEST_F(CliMonitor, CtrlCDuringTheCalibrationWritesNothingAndSaysSo) {
  // The calibration log comes through a FIFO whose writer stops after 300 rows and tells the test
  // so: monitor is then inside the calibration, waiting, when SIGINT comes; the writer then
  // closes its end.
  const std::string script =
      "cd " + dir_ + " && rm -f cal written go && mkfifo cal && " +
      "{ (exec 3>cal; head -n 300 clean.csv >&3; : > written; "
      "while [ ! -e go ]; do sleep 0.05; done) & writer=$!; " +
      DYNID_BIN +
      " monitor --arm puma560 --data pushed.csv --calibration cal --out stopped 2> stopped.err & "
      "pid=$!; for i in $(seq 1200); do [ -e written ] && break; sleep 0.1; done; "
      "kill -INT $pid; : > go; wait $pid; code=$?; wait $writer; exit $code; }";
  std::filesystem::remove_all(dir_ + "/stopped");
  const int status = std::system(("bash -c '" + script + "'").c_str());
  const std::string err = readFile(dir_ + "/stopped.err");
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  EXPECT_TRUE(contains(err, "interrupted (Ctrl-C) before the thresholds were set: nothing written"))
      << err;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/stopped"));
}

}  // namespace
}  // namespace dynid
