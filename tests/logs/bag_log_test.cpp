// Recordings into prepare: a ROS 1 bag written by ROS's own writer
// (tools/make_ros1_bag_fixtures.py) gives the same dataset as the same samples in a table; joints
// are matched by name to the robot's (any order, others ignored), and what cannot be matched is
// named.
#include "analysis/logs/bag_log.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>

#include "analysis/logs/prepare.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/fixtures.hpp"
#include "tests/common/joint_state_db3.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/scratch_dataset.hpp"

namespace dynid {
namespace {

using test::bagFixtures;

/// The fixture's samples (tools/make_ros1_bag_fixtures.py) as a table, joints in `order` (the
/// numbers in the names: joint1 1, joint2 2, gripper 3).
std::string tableOfTheFixture(const std::vector<int>& order) {
  std::ostringstream out;
  out.precision(17);
  out << "t";
  for (const char* kind : {"q", "dq", "tau"})
    for (int j : order) out << "," << kind << j;
  out << "\n";
  for (int k = 0; k < 200; ++k) {
    out << k * 1e-3;
    for (int j : order) out << "," << 0.1 * j * std::sin(0.01 * k);
    for (int j : order) out << "," << 0.001 * j * std::cos(0.01 * k);
    for (int j : order) out << "," << 2.0 * j + 0.5 * k;
    out << "\n";
  }
  const std::string path = test::tempPath("fixture_table.csv");
  writeFileAtomically(path, out.str());
  return path;
}

PrepareOptions unfiltered() {
  PrepareOptions o;
  o.cutoff = 0.0;  // 0.2 s of data: no room for a filter's transient
  o.trim = 0.0;
  return o;
}

TEST(BagLog, ARos1BagPreparesAsTheSameSamplesInATable) {
  LogSource table;
  table.tables = {tableOfTheFixture({2, 1, 3})};  // the messages' order: joint2, joint1, gripper
  table.time_column = "t";
  table.q_columns = "q2,q1,q3";
  table.dq_columns = "dq2,dq1,dq3";
  table.tau_columns = "tau2,tau1,tau3";
  const PrepareOutcome expected = prepareLog(table, unfiltered());
  for (const char* compression : {"none", "bz2", "lz4"}) {
    LogSource bag;
    bag.tables = {(bagFixtures() / ("joint_states_" + std::string(compression) + ".bag")).string()};
    const PrepareOutcome o = prepareLog(bag, unfiltered());
    SCOPED_TRACE(compression);
    // The table's stamps are k 1e-3 written in 17 digits, the bag's integer ns: the same times to
    // the last bit or two, hence 1e-12 (the bound), not equality.
    for (auto member : {&Trajectory::q, &Trajectory::dq, &Trajectory::ddq, &Trajectory::tau})
      EXPECT_LT(((o.train.*member) - (expected.train.*member)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((o.train.time - expected.train.time).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(o.time_origin, 1700000000.0L);
    EXPECT_EQ(o.columns[0].q, (std::vector<std::string>{"joint2", "joint1", "gripper"}));
  }
}

TEST(BagLog, JointsAreMatchedByNameToTheRobotsAndTheRestIgnored) {
  LogSource bag;
  bag.tables = {(bagFixtures() / "joint_states_bz2.bag").string()};
  bag.joint_names = {"joint1", "joint2"};  // the robot's order; the gripper is not the robot's
  const RawSignals s = readBagLog(bag, bag.tables[0]);
  ASSERT_EQ(s.n, 2);
  ASSERT_TRUE(s.has_dq);
  for (Eigen::Index k = 0; k < s.rows; ++k)
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(s.q()(k, j), 0.1 * (j + 1) * std::sin(0.01 * static_cast<double>(k)));
      EXPECT_EQ(s.tau()(k, j), 2.0 * (j + 1) + 0.5 * static_cast<double>(k));
    }
  bag.joint_names = {"joint1", "elbow", "wrist"};
  try {
    readBagLog(bag, bag.tables[0]);
    ADD_FAILURE() << "joints the messages lack were accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("elbow, wrist"), std::string::npos) << what;
    EXPECT_NE(what.find("joint2, joint1, gripper"), std::string::npos) << what;
  }
  // A topic of another type, and one nobody recorded.
  bag.joint_names = {};
  bag.topic = "/chatter";
  EXPECT_THROW(readBagLog(bag, bag.tables[0]), InputError);
  bag.topic = "/nothing";
  EXPECT_THROW(readBagLog(bag, bag.tables[0]), InputError);
  // Receive time: the recorder stamped each message with its header stamp here.
  bag.topic = "";
  bag.receive_time = true;
  EXPECT_EQ(readBagLog(bag, bag.tables[0]).values.col(0), s.values.col(0));
}

// More messages than one of readBagLog's blocks of rows (4096): every value in its place, with the
// efforts in the position messages and joined from a second topic.
TEST(BagLog, ALongRecordingReadsBackRowForRowAcrossBlocks) {
  constexpr int kMessages = 10000;
  const std::int64_t origin = 1700000000LL * 1000000000;
  const std::vector<std::string> names = {"a", "b"};
  const auto values = [](int k) {
    return std::array<double, 6>{1e-4 * k, -2e-4 * k, 0.1 + k, 0.2 - k, 3.0 * k, -0.5 * k};
  };
  const std::string path = test::tempPath("long.db3");
  {
    test::JointStateDb3 db3(path, {"/joint_states", "/efforts"});
    for (int k = 0; k < kMessages; ++k) {
      const std::int64_t ns = origin + k * 1000000LL;
      const std::array<double, 6> v = values(k);
      db3.add(ns, ns, names, v.data(), v.data() + 2, v.data() + 4, 0);
      db3.add(ns, ns, names, v.data(), nullptr, v.data() + 4, 1);
    }
    db3.close();
  }
  LogSource in_messages, separate;
  in_messages.tables = separate.tables = {path};
  in_messages.topic = separate.topic = "/joint_states";
  separate.effort_topic = "/efforts";
  // With a scratch directory, the samples go to a scratch file as they are read (not when the
  // efforts are joined from a second topic): the same values, column by column.
  const std::string scratch = test::tempPath("scratch");
  std::filesystem::create_directories(scratch);
  for (const LogSource& source : {in_messages, separate})
    for (const std::string& dir : {std::string(), scratch}) {
      SCOPED_TRACE(source.effort_topic + " " + dir);
      const RawSignals s = readBagLog(source, path, dir);
      EXPECT_EQ(s.spilled != nullptr, !dir.empty() && source.effort_topic.empty());
      ASSERT_EQ(s.rows, kMessages);
      ASSERT_TRUE(s.has_dq);
      ASSERT_EQ(s.numColumns(), 7);
      EXPECT_EQ(s.time_origin, 1700000000.0L);
      std::vector<Eigen::VectorXd> columns;
      for (int c = 0; c < s.numColumns(); ++c) columns.push_back(s.column(c));
      for (Eigen::Index k = 0; k < s.rows; ++k) {
        const auto i = static_cast<int>(k);
        const std::array<double, 6> v = values(i);
        ASSERT_EQ(columns[0][k], static_cast<double>(k * 1000000LL) * 1e-9) << k;
        for (int j = 0; j < 2; ++j) {
          ASSERT_EQ(columns[1 + j][k], v[j]) << k;      // q
          ASSERT_EQ(columns[3 + j][k], v[4 + j]) << k;  // tau
          ASSERT_EQ(columns[5 + j][k], v[2 + j]) << k;  // dq
        }
      }
    }
  EXPECT_TRUE(std::filesystem::is_empty(scratch));  // the scratch files went with the signals
}

// A recording prepared through scratch files (its samples spilled as they are read, the joints
// prepared from there, the datasets kept in scratch files: dynid prepare's path, whatever the
// length) gives the numbers prepared in memory, bit for bit, through what prepare cleans: rest at
// the start, a repeated stamp, stamps out of order, stalled repeats and a gap; logged and derived
// velocities, both derivative methods.
TEST(BagLog, PreparedThroughScratchFilesItGivesTheBitsPreparedInMemory) {
  const std::vector<std::string> names = {"a", "b", "c"};
  const std::string path = test::tempPath("scratch.db3");
  {
    test::JointStateDb3 db3(path);
    std::int64_t ns = 1700000000LL * 1000000000;
    for (int k = 0; k < 9000; ++k) {
      const double t = std::max(0.0, 1e-3 * k - 1.0);  // at rest for the first second
      std::array<double, 3> q{}, dq{}, tau{};
      for (int j = 0; j < 3; ++j) {
        const double w = 1.0 + j;
        q[j] = 0.5 * std::sin(w * t) + 1e-4 * std::sin(97.0 * k);  // with a little "noise"
        dq[j] = 0.5 * w * std::cos(w * t);
        tau[j] = 2.0 * q[j] - 0.3 * dq[j] + 0.01 * std::cos(41.0 * k);
      }
      if (k >= 3000 && k < 3004) {  // the logger stalls: the same sample, new stamps
        static std::array<double, 3> held_q, held_dq, held_tau;
        if (k == 3000) held_q = q, held_dq = dq, held_tau = tau;
        q = held_q, dq = held_dq, tau = held_tau;
      }
      ns += k == 6000 ? 100000000LL : 1000000LL + (k % 7) * 20000LL;  // a gap, and jitter
      std::int64_t stamp = ns;
      if (k == 2001) stamp -= 1500000LL;  // before the previous message's
      db3.add(stamp, ns, names, q.data(), dq.data(), tau.data());
      if (k == 1500) db3.add(stamp, ns, names, q.data(), dq.data(), tau.data());  // repeated
    }
    db3.close();
  }
  LogSource source;
  source.tables = {path};
  PrepareOptions plain;
  plain.validate_fraction = 0.2;
  PrepareOptions derived = plain;
  derived.derive_dq = true;
  PrepareOptions savgol = derived;
  savgol.savitzky_golay = true;
  const std::string scratch = test::tempPath("scratch");
  std::filesystem::create_directories(scratch);
  for (const PrepareOptions& o : {plain, derived, savgol}) {
    const PrepareOutcome memory = prepareLog(source, o, 3);
    const PrepareOutcome spilled = prepareLog(source, o, 3, scratch);
    EXPECT_EQ(memory.repeated_stamps, 1);
    EXPECT_EQ(memory.unsorted_stamps, 1);
    EXPECT_EQ(memory.stalled_repeats, 3);
    ASSERT_EQ(memory.runs.size(), 2u);
    ASSERT_EQ(memory.rest.size(), 1u);
    // 1000 samples at rest, 1.06 ms apart on average, then the motion's first 1 % of its range.
    EXPECT_GT(memory.rest[0].leading, 1.06);
    EXPECT_LT(memory.rest[0].leading, 1.1);
    for (int PrepareOutcome::*counts :
         {&PrepareOutcome::repeated_stamps, &PrepareOutcome::unsorted_stamps,
          &PrepareOutcome::stalled_repeats, &PrepareOutcome::raw_samples})
      EXPECT_EQ(spilled.*counts, memory.*counts);
    EXPECT_EQ(spilled.warnings, memory.warnings);
    EXPECT_EQ(spilled.rest[0].leading, memory.rest[0].leading);
    EXPECT_EQ(spilled.rest[0].trailing, memory.rest[0].trailing);
    EXPECT_EQ(spilled.gaps, memory.gaps);
    EXPECT_EQ(spilled.tau_noise, memory.tau_noise);
    EXPECT_EQ(spilled.q_spectrum.density, memory.q_spectrum.density);
    test::expectSameSamples(memory.train, spilled.scratch_train.get(), 1000);
    test::expectSameSamples(memory.validate, spilled.scratch_validate.get(), 1000);
  }
  EXPECT_TRUE(std::filesystem::is_empty(scratch));
}

// A driver's prefix on every name (Franka's "panda_joint1" for "joint1", beside its gripper's
// "panda_finger_joint1"): matched under the one prefix every joint carries, said in a warning;
// two prefixes that fit alike (two arms) are refused, and the names themselves win.
TEST(BagLog, PrefixedJointNamesMatchUnderOnePrefixAndSaySo) {
  const auto write = [](const std::string& name, const std::vector<std::string>& names) {
    const std::string path = test::tempPath(name);
    test::JointStateDb3 db3(path);
    for (int k = 0; k < 50; ++k) {
      const std::int64_t ns = 1700000000LL * 1000000000 + k * 1000000LL;
      std::vector<double> v(names.size());
      for (std::size_t j = 0; j < v.size(); ++j) v[j] = 0.1 * static_cast<double>(j + 1) + 1e-3 * k;
      db3.add(ns, ns, names, v.data(), v.data(), v.data(), 0);
    }
    db3.close();
    return path;
  };
  LogSource source;
  source.joint_names = {"joint1", "joint2"};
  source.tables = {write("prefixed.db3", {"panda_finger_joint1", "panda_joint2",
                                          "panda_finger_joint2x", "panda_joint1"})};
  const RawSignals s = readBagLog(source, source.tables[0]);
  EXPECT_EQ(s.q()(0, 0), 0.1 * 4);  // joint1: panda_joint1, the fourth name
  EXPECT_EQ(s.q()(0, 1), 0.1 * 2);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("with the prefix 'panda_' (panda_joint1 as joint1, ...)"),
            std::string::npos)
      << s.warnings[0];
  source.tables = {
      write("two_arms.db3", {"left_joint1", "left_joint2", "right_joint1", "right_joint2"})};
  try {
    readBagLog(source, source.tables[0]);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("under several prefixes (left_, right_): say which arm "
                                         "with `joint_prefix` left_"),
              std::string::npos)
        << e.what();
  }
  source.joint_prefix = "right_";  // the arm named
  const RawSignals right = readBagLog(source, source.tables[0]);
  EXPECT_EQ(right.q()(0, 0), 0.1 * 3);
  EXPECT_EQ(right.columns.q, (std::vector<std::string>{"right_joint1", "right_joint2"}));
  source.joint_prefix.clear();
  source.tables = {write("exact.db3", {"arm_joint1", "arm_joint2", "joint2", "joint1"})};
  const RawSignals exact = readBagLog(source, source.tables[0]);
  EXPECT_EQ(exact.q()(0, 0), 0.1 * 4);  // "joint1" itself
  EXPECT_TRUE(exact.warnings.empty());
  // A prefix without a separator, or one that only some joints carry: missing.
  source.tables = {write("no_separator.db3", {"xjoint1", "xjoint2"})};
  EXPECT_THROW(readBagLog(source, source.tables[0]), InputError);
  source.tables = {write("partly.db3", {"arm_joint1", "joint3"})};
  EXPECT_THROW(readBagLog(source, source.tables[0]), InputError);
  // The robot's names carry a prefix the messages lack (a description generated with a prefix,
  // a driver publishing without it): matched, said in a warning; without a separator, missing.
  source.joint_names = {"lbr_iiwa_joint_1", "lbr_iiwa_joint_2"};
  source.tables = {write("robot_prefixed.db3", {"iiwa_joint_2", "iiwa_joint_1", "tool_joint"})};
  const RawSignals unprefixed = readBagLog(source, source.tables[0]);
  EXPECT_EQ(unprefixed.q()(0, 0), 0.1 * 2);  // lbr_iiwa_joint_1: iiwa_joint_1, the second name
  EXPECT_EQ(unprefixed.q()(0, 1), 0.1 * 1);
  ASSERT_EQ(unprefixed.warnings.size(), 1u);
  EXPECT_NE(
      unprefixed.warnings[0].find(
          "carry the prefix 'lbr_' the messages lack (lbr_iiwa_joint_1 as iiwa_joint_1, ...)"),
      std::string::npos)
      << unprefixed.warnings[0];
  source.joint_names = {"xjoint1", "xjoint2"};
  source.tables = {write("robot_no_separator.db3", {"joint1", "joint2"})};
  EXPECT_THROW(readBagLog(source, source.tables[0]), InputError);
}
}  // namespace
}  // namespace dynid
