// ROS 1 bags written by ROS's own writer (Debian's python3-rosbag: tools/make_ros1_bag_fixtures.py)
// read back exactly, uncompressed, bz2 and lz4; topics filtered; every truncation refused with the
// file and byte offset.
#include "data/bags/ros1_bag.hpp"

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/bags/ros_messages.hpp"
#include "data/io.hpp"
#include "tests/common/fixtures.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::bags {
namespace {

using test::bagFixtures;

TEST(Ros1Bag, JointStatesFromRosbagReadBackExactlyWhateverTheCompression) {
  const std::vector<std::string> names = {"joint2", "joint1", "gripper"};
  const double number[] = {2.0, 1.0, 3.0};
  for (const char* compression : {"none", "bz2", "lz4"}) {
    const std::string path =
        (bagFixtures() / ("joint_states_" + std::string(compression) + ".bag")).string();
    SCOPED_TRACE(path);
    int k = 0, chatter = 0;
    readRos1Bag(path, {}, [&](const BagMessage& m) {
      if (m.topic == "/chatter") {
        EXPECT_EQ(m.type, "std_msgs/String");
        ++chatter;
        return;
      }
      EXPECT_EQ(m.topic, "/joint_states");
      EXPECT_EQ(m.type, kJointStateRos1);
      EXPECT_EQ(m.encoding, Encoding::kRos1);
      EXPECT_EQ(m.receive_ns, 1700000000LL * 1000000000 + k * 1000000LL);
      JointStateMessage js;
      decodeJointStateRos1(m.data, *m.file, m.offset, js);
      EXPECT_EQ(js.stamp_ns, m.receive_ns);
      EXPECT_EQ(js.name, names);
      ASSERT_EQ(js.position.size(), 3u);
      for (int j = 0; j < 3; ++j) {
        // The writer's own doubles, bit for bit (the same expression in Python and here).
        EXPECT_EQ(js.position[j], 0.1 * number[j] * std::sin(0.01 * k));
        EXPECT_EQ(js.velocity[j], 0.001 * number[j] * std::cos(0.01 * k));
        EXPECT_EQ(js.effort[j], 2.0 * number[j] + 0.5 * k);
      }
      ++k;
    });
    EXPECT_EQ(k, 200);
    EXPECT_EQ(chatter, 4);
    int only = 0;
    readRos1Bag(path, {"/chatter"}, [&](const BagMessage&) { ++only; });
    EXPECT_EQ(only, 4);
  }
}

TEST(Ros1Bag, EveryTruncationAndAForeignFileAreRefusedWithTheOffset) {
  const std::string whole = readFile((bagFixtures() / "joint_states_bz2.bag").string());
  const std::string path = test::tempPath("cut.bag");
  int refused = 0, read = 0;
  // 80 cuts spread over the file (each one decompresses what it can: seconds under ASan).
  for (std::size_t length = 0; length < whole.size(); length += whole.size() / 80 + 1) {
    writeFileAtomically(path, whole.substr(0, length));
    try {
      readRos1Bag(path, {}, [](const BagMessage&) {});
      ++read;  // a cut between two records: a shorter, whole bag
    } catch (const ParseError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
  writeFileAtomically(path, "\x89MCAP0\r\n");
  EXPECT_THROW(readRos1Bag(path, {}, [](const BagMessage&) {}), ParseError);
}

}  // namespace
}  // namespace dynid::bags
