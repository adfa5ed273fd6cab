#include "analysis/monitor/monitor.hpp"
#include "analysis/monitor/states.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/puma560.hpp"
#include "tests/common/error_text.hpp"
#include "tests/common/joint_state_db3.hpp"
#include "tests/common/monitor_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::jointPush;
using test::pushedPuma;

/// Records when each event was reported: the sample count at that moment.
struct Recorder : MonitorEventSink {
  const long long* fed = nullptr;
  std::vector<long long> started_at;
  std::vector<MonitorEvent> ended_events;
  void started(const MonitorEvent&) override { started_at.push_back(*fed); }
  void ended(const MonitorEvent& e) override { ended_events.push_back(e); }
};

class MonitorRun : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = makePuma560();
    clean_ = test::tempPath("monitor_clean.csv");
    writeDatasetCsv(clean_, pushedPuma(model_, 6.0, {}, nullptr, 0.05));
  }
  Model model_;
  std::string clean_;
};

/// A PUMA trajectory as stdin lines (t,q..,dq..,tau.. after its header), counting the lines fed.
std::function<bool(std::string&)> sampleLines(const Trajectory& t, long long& fed) {
  return [&t, &fed](std::string& line) {
    if (fed > t.numSamples()) return false;
    if (fed == 0) {
      line = "t,q1,q2,q3,q4,q5,q6,dq1,dq2,dq3,dq4,dq5,dq6,tau1,tau2,tau3,tau4,tau5,tau6";
    } else {
      const int k = static_cast<int>(fed - 1);
      std::ostringstream row;
      row.precision(17);
      row << t.time[k];
      for (const Eigen::MatrixXd* m : {&t.q, &t.dq, &t.tau})
        for (int j = 0; j < 6; ++j) row << ',' << (*m)(j, k);
      line = row.str();
    }
    ++fed;
    return true;
  };
}

// Streamed on stdin (here a function), an event is reported at the sample that crossed.
TEST_F(MonitorRun, AStreamedEventIsReportedAtTheCrossingSample) {
  Eigen::MatrixXd applied;
  const Trajectory pushed = pushedPuma(model_, 3.0, {jointPush(2, 10.0, 1.5, 0.2)}, &applied, 0.05);
  long long fed = 0;
  Recorder recorder;
  recorder.fed = &fed;
  MonitorRequest request;
  request.arm = "puma560";
  request.data_file = "-";
  request.calibration_file = clean_;
  request.sink = &recorder;
  request.next_line = sampleLines(pushed, fed);
  const MonitorOutcome out = monitorRun(request);
  ASSERT_EQ(out.events.size(), 1u);
  ASSERT_EQ(recorder.started_at.size(), 1u);
  const MonitorEvent& e = out.events[0];
  EXPECT_EQ(e.joints, std::vector<int>{2});
  // Within 50 ms of the push, and reported before the next line was read.
  EXPECT_GE(e.start, 1.5);
  EXPECT_LT(e.start, 1.55);
  const long long crossing_line = 1 + std::lround(e.start * 1000) + 1;  // header, then sample k
  EXPECT_EQ(recorder.started_at[0], crossing_line);
  EXPECT_FALSE(out.has_direct);
  EXPECT_EQ(out.samples, pushed.numSamples());
}

std::string recording(const std::string& name, const Model& model, const Trajectory& tr,
                      bool velocity, int late, int repeat, int nan_at, int late_by);

// Ctrl-C (the flag) during a dataset or a recording: stopped after the current sample, the events
// so far kept, the open one marked.
TEST_F(MonitorRun, StoppedMidEventItKeepsTheEventsSoFar) {
  const Trajectory pushed = pushedPuma(
      model_, 4.0, {jointPush(1, 15.0, 1.0, 0.1), jointPush(2, 12.0, 3.0, 0.5)}, nullptr, 0.05);
  const std::string pushed_file = test::tempPath("monitor_pushed.csv");
  writeDatasetCsv(pushed_file, pushed);
  for (const std::string& data :
       {pushed_file, recording("monitor_stopped.db3", model_, pushed, true, -1, -1, -1, 1)}) {
    std::atomic<bool> stop{false};
    struct StopAtSecondEvent : MonitorEventSink {
      std::atomic<bool>* stop;
      void started(const MonitorEvent& e) override {
        if (e.start > 2.0) stop->store(true);
      }
      void ended(const MonitorEvent&) override {}
    } sink;
    sink.stop = &stop;
    MonitorRequest request;
    request.arm = "puma560";
    request.data_file = data;
    request.calibration_file = clean_;
    request.sink = &sink;
    request.control.stop = &stop;
    const MonitorOutcome out = monitorRun(request);
    EXPECT_TRUE(out.interrupted) << data;
    ASSERT_EQ(out.events.size(), 2u) << data;
    EXPECT_FALSE(out.events[0].open);
    EXPECT_TRUE(out.events[1].open);  // closed at the stop, marked open
    EXPECT_LT(out.samples, 3100) << data;
  }
}

// Ctrl-C during the calibration gives no thresholds (an error, not thresholds from a part of the
// log); after it, while a stream waits for its header, the thresholds stand and no sample is
// judged.
TEST_F(MonitorRun, StoppedBeforeItsFirstSampleItKeepsOnlyFinishedThresholds) {
  std::atomic<bool> stop{true};
  MonitorRequest request;
  request.arm = "puma560";
  request.data_file = "-";
  request.calibration_file = clean_;
  request.control.stop = &stop;
  request.next_line = [](std::string&) { return false; };
  EXPECT_NE(test::errorText<InputError>([&] {
              monitorRun(request);
            }).find("stopped during the calibration"),
            std::string::npos);
  stop = false;
  request.next_line = [&stop](std::string&) {  // a reader that gives up its wait on Ctrl-C
    stop = true;
    return false;
  };
  const MonitorOutcome out = monitorRun(request);
  EXPECT_TRUE(out.interrupted);
  EXPECT_EQ(out.samples, 0);
  EXPECT_TRUE(out.events.empty());
  ASSERT_EQ(out.thresholds.values.size(), 6);
  EXPECT_TRUE((out.thresholds.values.array() > 0.0).all()) << out.thresholds.values.transpose();
  // Without Ctrl-C, a stream that ends before its header is a malformed stream.
  stop = false;
  request.next_line = [](std::string&) { return false; };
  EXPECT_NE(test::errorText<ParseError>([&] { monitorRun(request); }).find("no header"),
            std::string::npos);
}

TEST_F(MonitorRun, RefusesThresholdsOfOtherJointsAndBadRequests) {
  MonitorRequest request;
  request.arm = "puma560";
  request.data_file = clean_;
  EXPECT_THROW(monitorRun(request), InputError);  // no threshold source
  const std::string other = test::writeTemp("monitor_other_thresholds.json", R"({
    "schema_version": 1, "kind": "dynid.monitor_thresholds", "robot": "two",
    "joints": ["a", "b"], "residual": "observer", "gain": [100, 100], "thresholds": [1, 1],
    "source": "x"})");
  request.thresholds_file = other;
  try {
    monitorRun(request);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("monitor_other_thresholds.json"), std::string::npos);
  }
  request.thresholds_file.clear();
  request.calibration_file = clean_;
  request.arm = "panda";  // a log of another robot
  EXPECT_THROW(monitorRun(request), InputError);
  request.arm = "puma560";
  request.hold = -1.0;
  EXPECT_THROW(monitorRun(request), InputError);
}

/// The trajectory as a rosbag2 recording as a robot's driver publishes it: the joints by name in
/// another order beside a gripper joint, header stamps on the epoch clock (nanoseconds); sample
/// `late` is received after sample late + late_by (its header stamp out of order) and sample
/// `repeat` twice. No velocity when `velocity`
/// is false; the velocity of joint 2 at sample `nan_at` not a number (when >= 0).
std::string recording(const std::string& name, const Model& model, const Trajectory& tr,
                      bool velocity = true, int late = -1, int repeat = -1, int nan_at = -1,
                      int late_by = 1) {
  const std::string path = test::tempPath(name);
  const int n = model.numJoints();
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) order[static_cast<std::size_t>(j)] = (j + 2) % n;
  std::vector<std::string> names;
  for (int j : order) names.push_back(model.joint_names[static_cast<std::size_t>(j)]);
  names.push_back("gripper");
  test::JointStateDb3 db3(path);
  const auto put = [&](int k) {
    const std::int64_t ns = 1700000000000000000LL + std::llround(tr.time[k] * 1e9);
    std::vector<double> q, dq, tau;
    for (int j : order) {
      q.push_back(tr.q(j, k));
      dq.push_back(k == nan_at && j == 2 ? std::nan("") : tr.dq(j, k));
      tau.push_back(tr.tau(j, k));
    }
    q.push_back(0.01), dq.push_back(0.0), tau.push_back(0.0);
    // Received 0.3 ms after its stamp; the late one after sample late + late_by (the recorder's
    // order).
    const int received = k == late ? k + late_by : k;
    const std::int64_t receive_ns =
        1700000000000000000LL + std::llround(tr.time[received] * 1e9) + 300000 + (k == late);
    db3.add(ns, receive_ns, names, q.data(), velocity ? dq.data() : nullptr, tau.data());
  };
  for (int k = 0; k < tr.numSamples(); ++k) {
    if (k == late) continue;
    put(k);
    if (late >= 0 && k == late + late_by) put(late);
    if (k == repeat) put(k);
  }
  db3.close();
  return path;
}

// A recording (JointState with velocities) is monitored at its own stamps, joints by name: the
// same thresholds, residuals and events as the same samples in a dataset, messages out of order
// and repeated included.
TEST_F(MonitorRun, ARecordingGivesTheSameEventsAsItsSamplesInADataset) {
  const Trajectory clean = pushedPuma(model_, 6.0, {}, nullptr, 0.05);
  const Trajectory pushed = pushedPuma(model_, 3.0, {jointPush(2, 10.0, 1.5, 0.2)}, nullptr, 0.05);
  const std::string pushed_csv = test::tempPath("monitor_pushed_for_bag.csv");
  writeDatasetCsv(pushed_csv, pushed);
  MonitorRequest from_csv;
  from_csv.arm = "puma560";
  from_csv.data_file = pushed_csv;
  from_csv.calibration_file = clean_;
  const MonitorOutcome a = monitorRun(from_csv);
  MonitorRequest from_bag = from_csv;
  from_bag.data_file = recording("monitor_pushed.db3", model_, pushed, true, 700, 1200);
  from_bag.calibration_file = recording("monitor_clean.db3", model_, clean);
  const MonitorOutcome b = monitorRun(from_bag);
  // The stamps are whole nanoseconds: times agree to 1e-9 s, residuals to round-off of that.
  ASSERT_EQ(a.thresholds.values.size(), 6);
  EXPECT_LT((a.thresholds.values - b.thresholds.values).norm(), 1e-8 * a.thresholds.values.norm());
  ASSERT_EQ(a.events.size(), 1u);
  ASSERT_EQ(b.events.size(), 1u);
  EXPECT_EQ(a.events[0].joints, b.events[0].joints);
  EXPECT_NEAR(a.events[0].start, b.events[0].start, 1e-8);
  EXPECT_NEAR(a.events[0].end, b.events[0].end, 1e-8);
  EXPECT_NEAR(a.events[0].peak, b.events[0].peak, 1e-8 * a.events[0].peak);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_LT((a.observer_rms - b.observer_rms).norm(), 1e-8 * a.observer_rms.norm());
  EXPECT_TRUE(a.has_direct);
  EXPECT_FALSE(b.has_direct);  // a recording has no ddq
  bool repeated = false;
  for (const std::string& w : b.warnings)
    repeated = repeated || w.find("1 message(s) repeated an earlier stamp") != std::string::npos;
  EXPECT_TRUE(repeated);
  // A driver that names the joints A1..A6: refused as lacking the arm's joints, then read with
  // the messages' names given for them (--joint-names): the same events. One name short, or the
  // names with a dataset CSV (nothing to name), is refused.
  Model renamed = model_;
  for (int j = 0; j < 6; ++j)
    renamed.joint_names[static_cast<std::size_t>(j)] = "A" + std::to_string(j + 1);
  MonitorRequest named = from_bag;
  named.data_file = recording("monitor_pushed_a.db3", renamed, pushed, true, 700, 1200);
  named.calibration_file = recording("monitor_clean_a.db3", renamed, clean);
  EXPECT_THROW(monitorRun(named), InputError);
  named.joint_names = renamed.joint_names;
  const MonitorOutcome c = monitorRun(named);
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].joints, b.events[0].joints);
  EXPECT_EQ(c.events[0].peak, b.events[0].peak);
  named.joint_names.pop_back();
  EXPECT_THROW(monitorRun(named), InputError);
  MonitorRequest csv_named = from_csv;
  csv_named.joint_names = renamed.joint_names;
  EXPECT_THROW(monitorRun(csv_named), InputError);
}

// Messages are put in stamp order within a 1 s window: one received 0.5 s late is used, one 1.5 s
// late is skipped and counted.
TEST_F(MonitorRun, ARecordingsLateMessagesAreOrderedWithinItsWindow) {
  const Trajectory log = pushedPuma(model_, 2.5, {}, nullptr, 0.05);
  MonitorRequest request;
  request.arm = "puma560";
  request.calibration_file = clean_;
  request.data_file = recording("monitor_late_0.5.db3", model_, log, true, 100, -1, -1, 500);
  const MonitorOutcome in_window = monitorRun(request);
  EXPECT_EQ(in_window.samples, log.numSamples());
  for (const std::string& w : in_window.warnings)
    EXPECT_EQ(w.find("skipped"), std::string::npos) << w;
  request.data_file = recording("monitor_late_1.5.db3", model_, log, true, 100, -1, -1, 1500);
  const MonitorOutcome late = monitorRun(request);
  EXPECT_EQ(late.samples, log.numSamples() - 1);
  bool counted = false;
  for (const std::string& w : late.warnings)
    counted = counted || w.find(
                             "1 message(s) repeated an earlier stamp (or came more than 1 s "
                             "after later-stamped ones) and were skipped") != std::string::npos;
  EXPECT_TRUE(counted);
}

// Efforts on a topic of their own (position and velocity on one, effort on another, as some
// drivers publish them): read whole and joined at the positions' stamps, the same events.
TEST_F(MonitorRun, ARecordingWithItsEffortsOnAnotherTopic) {
  const Trajectory pushed = pushedPuma(model_, 3.0, {jointPush(2, 10.0, 1.5, 0.2)}, nullptr, 0.05);
  const std::string csv = test::tempPath("monitor_split_efforts.csv");
  writeDatasetCsv(csv, pushed);
  const std::string bag = test::tempPath("monitor_split_efforts.db3");
  {
    test::JointStateDb3 db3(bag, {"/joint_states", "/joint_efforts"});
    for (int k = 0; k < pushed.numSamples(); ++k) {
      const Eigen::VectorXd q = pushed.q.col(k), dq = pushed.dq.col(k), tau = pushed.tau.col(k);
      const std::int64_t ns = 1700000000000000000LL + std::llround(pushed.time[k] * 1e9);
      db3.add(ns, ns + 100000, model_.joint_names, q.data(), dq.data(), nullptr, 0);
      db3.add(ns, ns + 200000, model_.joint_names, nullptr, nullptr, tau.data(), 1);
    }
    db3.close();
  }
  MonitorRequest request;
  request.arm = "puma560";
  request.calibration_file = clean_;
  request.data_file = csv;
  const MonitorOutcome a = monitorRun(request);
  request.data_file = bag;
  request.topic = "/joint_states";
  request.effort_topic = "/joint_efforts";
  const MonitorOutcome b = monitorRun(request);
  ASSERT_EQ(a.events.size(), 1u);
  ASSERT_EQ(b.events.size(), 1u);
  EXPECT_EQ(a.events[0].joints, b.events[0].joints);
  EXPECT_NEAR(a.events[0].start, b.events[0].start, 1e-8);
  EXPECT_EQ(a.samples, b.samples);
  // Nanosecond stamps, as above.
  EXPECT_LT((a.observer_rms - b.observer_rms).norm(), 1e-8 * a.observer_rms.norm());
  // Without the effort topic, the positions' messages carry none: refused, naming the options.
  request.effort_topic.clear();
  const std::string text = test::errorText<InputError>([&] { monitorRun(request); });
  EXPECT_NE(text.find("carry no effort"), std::string::npos) << text;
}

// An estimate identified from converted currents (its torque_source) monitoring a recording: a
// warning without torque constants (the efforts are taken as torques) or with other ones, none
// with the same.
TEST_F(MonitorRun, AnEstimateFromCurrentsWarnsWhenARecordingsConstantsDiffer) {
  const std::vector<std::string> names = standardParameterNames(model_.parameterLayout());
  const Eigen::VectorXd theta = model_.standardParameters();
  nlohmann::json values = nlohmann::json::object();
  for (std::size_t k = 0; k < names.size(); ++k)
    values[names[k]] = theta[static_cast<Eigen::Index>(k)];
  const std::vector<double> constants = {0.2, 0.25, 0.125, 0.5, 0.4, 0.0625};
  const nlohmann::json estimate = {{"schema_version", 1},
                                   {"kind", "dynid.estimate"},
                                   {"robot_spec", "puma560"},
                                   {"drive_terms", nlohmann::json::array()},
                                   {"standard_estimate", {{"note", "n"}, {"values", values}}},
                                   {"torque_source",
                                    {{"kind", "current"},
                                     {"torque_constants", constants},
                                     {"gear_ratios", nlohmann::json::array()}}}};
  const std::string file = test::tempPath("monitor_from_currents_estimate.json");
  std::ofstream(file) << estimate.dump();
  const Trajectory log = pushedPuma(model_, 2.0, {}, nullptr, 0.05);
  MonitorRequest request;
  request.arm = file;
  request.calibration_file = clean_;
  request.data_file = recording("monitor_from_currents.db3", model_, log);
  const auto warned = [&](const MonitorRequest& r, const std::string& text) {
    for (const std::string& w : monitorRun(r).warnings)
      if (w.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned(request,
                     "was identified from motor currents converted to torques (dynid prepare "
                     "`torque_constants` 0.2,0.25,0.125,0.5,0.4,0.0625); the recording's efforts "
                     "are taken as joint torques"));
  request.torque_constants = Eigen::Map<const Eigen::VectorXd>(constants.data(), 6);
  EXPECT_FALSE(warned(request, "motor currents"));
  EXPECT_FALSE(warned(request, "differ"));
  request.gear_ratios = Eigen::VectorXd::Constant(6, 2.0);
  EXPECT_TRUE(warned(request, "the torque constants and gear ratios given differ from those"));
  // A dataset CSV: its torques are converted already, no warning.
  MonitorRequest dataset;
  dataset.arm = file;
  dataset.calibration_file = clean_;
  dataset.data_file = clean_;
  EXPECT_FALSE(warned(dataset, "motor currents"));
}

// A current-sensing arm's recording and stdin samples: efforts in A, turned into torques by
// --torque-constants and --gear-ratios (as prepare --current): the same thresholds and events as
// the torques themselves. Dataset CSVs hold torques already: the constants are refused there.
TEST_F(MonitorRun, CurrentsBecomeTorquesThroughTheTorqueConstants) {
  const Trajectory clean = pushedPuma(model_, 6.0, {}, nullptr, 0.05);
  const Trajectory pushed = pushedPuma(model_, 3.0, {jointPush(2, 10.0, 1.5, 0.2)}, nullptr, 0.05);
  Eigen::VectorXd constants(6), ratios(6);
  constants << 0.2, 0.25, 0.125, 0.5, 0.4, 0.0625;  // N m/A
  ratios << 100, 80, 160, 50, 64, 64;
  const auto currents = [&](Trajectory t) {
    for (int j = 0; j < 6; ++j) t.tau.row(j) /= constants[j] * ratios[j];
    return t;
  };
  MonitorRequest torques;
  torques.arm = "puma560";
  torques.data_file = recording("monitor_torques.db3", model_, pushed);
  torques.calibration_file = recording("monitor_torques_clean.db3", model_, clean);
  const MonitorOutcome a = monitorRun(torques);
  MonitorRequest amps = torques;
  amps.data_file = recording("monitor_currents.db3", model_, currents(pushed));
  amps.calibration_file = recording("monitor_currents_clean.db3", model_, currents(clean));
  amps.torque_constants = constants;
  amps.gear_ratios = ratios;
  const MonitorOutcome b = monitorRun(amps);
  // Dividing and multiplying back rounds each torque by an ulp or two.
  EXPECT_LT((a.thresholds.values - b.thresholds.values).norm(), 1e-12 * a.thresholds.values.norm());
  ASSERT_EQ(a.events.size(), 1u);
  ASSERT_EQ(b.events.size(), 1u);
  EXPECT_EQ(b.events[0].joints, std::vector<int>{2});
  EXPECT_NEAR(a.events[0].start, b.events[0].start, 1e-12);
  // Without the constants the currents are taken as torques: another, wrong, set of thresholds.
  MonitorRequest raw = amps;
  raw.torque_constants = Eigen::VectorXd();
  raw.gear_ratios = Eigen::VectorXd();
  EXPECT_GT((monitorRun(raw).thresholds.values - a.thresholds.values).norm(),
            0.1 * a.thresholds.values.norm());
  // Stdin samples in A (calibrated on the recording in A: the constants apply to both).
  MonitorRequest stream = amps;
  stream.data_file = "-";
  const Trajectory sent = currents(pushed);
  long long fed = 0;
  stream.next_line = sampleLines(sent, fed);
  const MonitorOutcome c = monitorRun(stream);
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].joints, std::vector<int>{2});
  EXPECT_NEAR(c.events[0].start, a.events[0].start, 1e-9);  // the stamps as printed (17 digits)
  // Bad constants, and constants for datasets only.
  MonitorRequest bad = amps;
  bad.torque_constants = Eigen::VectorXd::Ones(5);
  const std::string count = test::errorText<InputError>([&] { monitorRun(bad); });
  EXPECT_NE(count.find("`torque_constants` has 5 values; the robot has 6"), std::string::npos)
      << count;
  bad.torque_constants = constants;
  bad.gear_ratios[3] = 0.0;
  const std::string zero = test::errorText<InputError>([&] { monitorRun(bad); });
  EXPECT_NE(zero.find("`gear_ratios`: the value of joint 4 must be finite and non-zero"),
            std::string::npos)
      << zero;
  MonitorRequest datasets;
  datasets.arm = "puma560";
  datasets.data_file = clean_;
  datasets.calibration_file = clean_;
  datasets.torque_constants = constants;
  const std::string csv = test::errorText<InputError>([&] { monitorRun(datasets); });
  EXPECT_NE(csv.find("the dataset CSVs given hold torques already"), std::string::npos) << csv;
}

TEST_F(MonitorRun, RefusesRecordingsItCannotMonitor) {
  const Trajectory pushed = pushedPuma(model_, 1.0, {}, nullptr, 0.05);
  MonitorRequest request;
  request.arm = "puma560";
  request.calibration_file = clean_;
  // No velocities: prepare first.
  request.data_file = recording("monitor_no_velocity.db3", model_, pushed, false);
  std::string text = test::errorText<InputError>([&] { monitorRun(request); });
  EXPECT_NE(text.find("carry no velocities"), std::string::npos) << text;
  EXPECT_NE(text.find("dynid prepare"), std::string::npos) << text;
  // A velocity that is not a number: the file, the time and the joint.
  request.data_file = recording("monitor_nan.db3", model_, pushed, true, -1, -1, 400);
  text = test::errorText<InputError>([&] { monitorRun(request); });
  EXPECT_NE(text.find("monitor_nan.db3"), std::string::npos) << text;
  EXPECT_NE(text.find("velocity of joint " + model_.joint_names[2] + " that is not finite"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("at 0.4 s"), std::string::npos) << text;
  // The direct residual needs ddq.
  request.data_file = recording("monitor_direct.db3", model_, pushed);
  request.residual = MonitorResidual::kDirect;
  text = test::errorText<InputError>([&] { monitorRun(request); });
  EXPECT_NE(text.find("a recording has no ddq"), std::string::npos) << text;
  // Another robot's recording: the joints it lacks, by name.
  request.residual = MonitorResidual::kObserver;
  request.arm = "panda";
  request.calibration_file.clear();
  request.thresholds_file = test::writeTemp("monitor_panda_thresholds.json", R"({
    "schema_version": 1, "kind": "dynid.monitor_thresholds", "robot": "panda",
    "joints": ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6", "joint7"],
    "residual": "observer", "gain": [100, 100, 100, 100, 100, 100, 100],
    "thresholds": [1, 1, 1, 1, 1, 1, 1], "source": "x"})");
  text = test::errorText<InputError>([&] { monitorRun(request); });
  EXPECT_NE(text.find("lack the robot's joints"), std::string::npos) << text;
}

/// The PUMA (perturbed by up to 20 %: the monitored nominal model is off) tracking its sinusoids
/// with stops (2 s of motion, 2.5 s holds), sensor noise of 0.05 N m and 1e-3 rad/s.
Trajectory pausedPuma(const Model& truth, double duration, double amplitude, std::uint64_t seed,
                      const std::vector<Disturbance>& pushes = {}) {
  TrackingController controller = test::pumaSinusoidController(truth, amplitude, 0.2, 0.6);
  Pauses p;
  p.move = 2.0, p.hold = 2.5, p.ramp = 0.4;
  controller.setPauses(p);
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = 0.05;
  options.noise_dq = 1e-3;
  options.seed = seed;
  return simulate(truth, controller, options, pushes);
}

TEST_F(MonitorRun, AtRestAPushIsJudgedByTheNoiseAtRestNotByTheMovingResidual) {
  const Model truth = perturbedModel(model_, 0.2, 5);
  const std::string calibration = test::tempPath("monitor_paused_clean.csv");
  writeDatasetCsv(calibration, pausedPuma(truth, 20.0, 0.5, 3));
  MonitorRequest request;
  request.arm = "puma560";
  request.calibration_file = calibration;
  request.data_file = calibration;
  const MonitorOutcome clean = monitorRun(request);
  const MonitorThresholds th = clean.thresholds;
  EXPECT_TRUE(clean.events.empty());  // a clean run raises no alarm
  ASSERT_EQ(th.values_at_rest.size(), 6);
  ASSERT_EQ(th.rest_velocity.size(), 6);
  // Four holds of 2.5 s, each at rest from kRestSettleSeconds after the stop (and the settling).
  EXPECT_GT(th.rest_seconds, 4 * (2.5 - kRestSettleSeconds) - 1.5);
  EXPECT_LT(th.rest_seconds, 4 * (2.5 - kRestSettleSeconds));
  EXPECT_NEAR(clean.rest_seconds, th.rest_seconds, 1e-9);
  // The residual at rest is the sensor's noise; moving, the model's error: thresholds at rest are
  // lower on every joint.
  EXPECT_TRUE((th.values_at_rest.array() < th.values.array()).all());
  // A push at rest on joint 3 three times its threshold at rest, below its moving threshold.
  const int j = 2;
  const double push = 3.0 * th.values_at_rest[j];
  ASSERT_LT(push, 0.8 * th.values[j]);
  const std::string pushed = test::tempPath("monitor_paused_pushed.csv");
  writeDatasetCsv(pushed,
                  pausedPuma(truth, 10.0, 0.35, 4, {jointPush(j, push, 7.5, 0.4)}));  // in a hold
  request.data_file = pushed;
  const auto during = [](const MonitorOutcome& o) {
    std::vector<MonitorEvent> out;
    for (const MonitorEvent& e : o.events)
      if (e.end >= 7.5 && e.start <= 7.95) out.push_back(e);
    return out;
  };
  const MonitorOutcome watched = monitorRun(request);
  const std::vector<MonitorEvent> found = during(watched);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_TRUE(found[0].at_rest);
  EXPECT_EQ(found[0].peak_joint, j);
  EXPECT_NEAR(found[0].start, 7.5, 0.1);  // the smoothing's 80 ms and the observer's 10 ms
  // The change at rest has the push's size, within what 0.4 s of 80 ms smoothing leaves and the
  // noise at rest (the threshold is a third of the push).
  EXPECT_NEAR(found[0].peak, push, 0.2 * push);
  // Nothing else but in the push's aftermath: released from the static friction that held it, the
  // arm settles for about a second, at rest, and that can raise an event of its own (one, 0.019
  // N m on joint 2 at 8.88 s, since the rest velocities leave out the log's cut sign runs).
  for (const MonitorEvent& e : watched.events) {
    if (e.start == found[0].start) continue;
    const bool aftermath = e.at_rest && e.start > 7.9 && e.start < 7.9 + 1.1 && e.peak < push;
    EXPECT_TRUE(aftermath) << "an event at " << e.start << " s, peak " << e.peak << " N m";
  }
  // The same thresholds without the arm states (a version 1 file): the push is not seen.
  const std::string v1_file =
      test::writeThresholdsWithoutStates(th, test::tempPath("monitor_thresholds_v1.json"));
  request.calibration_file.clear();
  request.thresholds_file = v1_file;
  const MonitorOutcome without = monitorRun(request);
  EXPECT_EQ(without.thresholds.values_at_rest.size(), 0);
  EXPECT_TRUE(during(without).empty());
}

// An arm held by its static friction, watched through a model of its own drive terms that carries
// no rest velocities (a model file, a URDF): the observer takes the friction at rest as the static
// friction's point value from the rest velocities the calibration measured, not Fc sign(noise).
TEST_F(MonitorRun, AtRestTheObserverTakesTheCalibrationsRestVelocities) {
  const Model truth = makePuma560(true);
  TrackingController controller = test::pumaSinusoidController(truth, 0.35, 0.2, 0.6);
  Pauses p;
  p.move = 2.0, p.hold = 2.5, p.ramp = 0.4;
  controller.setPauses(p);
  SimulationOptions options;
  options.duration = 12.0;
  options.noise_tau = 0.05;
  options.noise_dq = 1e-3;
  options.seed = 21;
  options.stiction = true;  // held at rest, as a real arm is
  const Trajectory log = simulate(truth, controller, options);
  const std::string calibration = test::tempPath("monitor_rest_friction.csv");
  const std::string arm = test::tempPath("monitor_rest_friction_arm.json");
  writeDatasetCsv(calibration, log);
  writeFileAtomically(arm, modelToJson(truth));
  MonitorRequest request;
  request.arm = arm;
  request.calibration_file = request.data_file = calibration;
  const MonitorOutcome o = monitorRun(request);
  ASSERT_EQ(o.thresholds.rest_velocity.size(), 6);
  ASSERT_EQ(o.model.rest_velocities.size(), 6u);
  for (int j = 0; j < 6; ++j)
    EXPECT_EQ(o.model.rest_velocities[j], o.thresholds.rest_velocity[j]) << "joint " << j + 1;
  EXPECT_TRUE(o.events.empty());
  // What it changes: the observer's residual from one sample at rest (every joint within its rest
  // velocity) to the next, with and without them (each hold has a level of its own, the static
  // friction's: the spread is the step's). Fc sign(noise) flips by 2 Fc at the noise's rate, which
  // the 10 ms observer passes in part.
  const auto restSpread = [&](const Model& model) {
    MomentumObserver observer(model, o.thresholds.gain);
    Eigen::VectorXd squares = Eigen::VectorXd::Zero(6), previous;
    int count = 0;
    bool follows = false;
    for (int k = 0; k < log.numSamples(); ++k) {
      const Eigen::VectorXd r =
          observer.update(log.time[k], log.q.col(k), log.dq.col(k), log.tau.col(k));
      const bool rest =
          (log.dq.col(k).cwiseAbs().array() <= o.thresholds.rest_velocity.array()).all();
      if (rest && follows) squares += (r - previous).cwiseAbs2(), ++count;
      follows = rest, previous = r;
    }
    EXPECT_GT(count, 2000);  // four holds of 2.5 s
    return Eigen::VectorXd((squares / (2.0 * count)).cwiseSqrt());
  };
  const Eigen::VectorXd with = restSpread(o.model), without = restSpread(truth);
  // Measured (seed 21): 0.36 against 1.29, 0.44 against 0.67, 0.098 against 0.32 N m on joints 1
  // to 3, 0.017 to 0.019 against 0.033 to 0.055 on the wrist. Joint 2's step is mostly the
  // velocity noise's (K M sigma_dq, its inertia the largest), which the friction does not change.
  for (int j = 0; j < 6; ++j) {
    const double bound = (j == 0 || j == 2 ? 0.5 : 0.75) * without[j];
    EXPECT_LT(with[j], bound) << "joint " << j + 1 << ": " << with[j] << " against " << without[j]
                              << " N m";
  }
}

TEST(MonitorThresholds, WhatACalibrationConfirms) {
  // 57 s of calibration (the real arm's): no alarm bounds the rate below 3 / 57 s at 95 %, 189
  // per hour; 0.1 per hour would need 30 hours; 200 per hour is confirmed.
  MonitorThresholds t;
  t.calibration_seconds = 57.0;
  t.false_alarms_per_hour = 0.1;
  const std::optional<CalibrationConfidence> c = calibrationConfidence(t);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->confirmed_per_hour, 3.0 / 57.0 * 3600.0, 1e-9);
  EXPECT_NEAR(c->needed_seconds, 30.0 * 3600.0, 1e-6);
  EXPECT_TRUE(c->extrapolated);
  t.false_alarms_per_hour = 200.0;
  EXPECT_FALSE(calibrationConfidence(t)->extrapolated);
  t.calibration_seconds = 0.0;  // read back from a file: nothing to say
  EXPECT_FALSE(calibrationConfidence(t).has_value());
}

}  // namespace
}  // namespace dynid
