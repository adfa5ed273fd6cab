// The JointState decoders: a ROS 2 CDR message laid out by hand from the XCDR1 rules (a 4-byte
// encapsulation header, each field aligned to its size from the payload's start), decoded field
// by field; every truncation of it refused with the file and byte offset. (Messages from ROS's own
// serializers come with the bag fixtures of the log import.) The floating base's Imu and
// WrenchStamped, encoded by tests/common/floating_bag from their definitions, in both encodings.
#include "data/bags/ros_messages.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "tests/common/floating_bag.hpp"

namespace dynid::bags {
namespace {

// stamp 12 s 345 ns, frame "base", names joint1 and joint2, positions (0.1, -0.2), velocities
// (1, 2), efforts (3.5, -4.5): 124 bytes, with padding before the first double of each array.
const unsigned char kJointState[] = {
    0x00, 0x01, 0x00, 0x00, 0x0c, 0x00, 0x00, 0x00, 0x59, 0x01, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00,
    0x62, 0x61, 0x73, 0x65, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00,
    0x6a, 0x6f, 0x69, 0x6e, 0x74, 0x31, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x6a, 0x6f, 0x69, 0x6e,
    0x74, 0x32, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x9a, 0x99, 0x99, 0x99,
    0x99, 0x99, 0xb9, 0x3f, 0x9a, 0x99, 0x99, 0x99, 0x99, 0x99, 0xc9, 0xbf, 0x02, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x40, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x0c, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x12, 0xc0,
};

TEST(RosMessages, ACdrJointStateDecodesFieldByField) {
  const std::string bytes(reinterpret_cast<const char*>(kJointState), sizeof(kJointState));
  JointStateMessage m;
  decodeJointStateCdr(bytes, "bag.mcap", 1000, m);
  EXPECT_EQ(m.stamp_ns, 12000000345);
  EXPECT_EQ(m.name, (std::vector<std::string>{"joint1", "joint2"}));
  EXPECT_EQ(m.position, (std::vector<double>{0.1, -0.2}));
  EXPECT_EQ(m.velocity, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(m.effort, (std::vector<double>{3.5, -4.5}));
  for (std::size_t length = 0; length + 1 < bytes.size(); ++length) {
    try {
      decodeJointStateCdr(bytes.substr(0, length), "bag.mcap", 1000, m);
      ADD_FAILURE() << "a message cut to " << length << " bytes was decoded";
    } catch (const ParseError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bag.mcap"), std::string::npos) << what;
      EXPECT_NE(what.find("at byte 1"), std::string::npos) << what;  // 1000 + its position
    }
  }
  std::string other = bytes;
  other[1] = 0x03;  // PL_CDR_LE: parameter lists, not plain CDR
  EXPECT_THROW(decodeJointStateCdr(other, "bag.mcap", 0, m), ParseError);
}

/// Every cut of a message short of its last field is refused naming the file and an offset.
template <class Message, class Decode>
void expectEveryCutRefused(const std::string& bytes, Decode decode) {
  Message m;
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    try {
      decode(bytes.substr(0, length), "bag.db3", 1000, m);
      ADD_FAILURE() << "a message cut to " << length << " of " << bytes.size()
                    << " bytes was decoded";
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("bag.db3"), std::string::npos) << e.what();
    }
  }
}

TEST(RosMessages, AnImuDecodesInBothEncodings) {
  test::ImuSample sample;
  sample.stamp_ns = 3000000007;
  sample.frame = "imu_link";
  sample.xyzw << 0.1, -0.2, 0.3, 0.927;
  sample.gyro << 0.5, -1.5, 2.5;
  sample.accel << 0.25, 0.125, 9.75;
  for (bool cdr : {true, false}) {
    const std::string bytes = cdr ? test::cdrImu(sample) : test::ros1Imu(sample);
    // CDR: header, the frame (13 bytes) padded to 8, then 37 doubles; ROS 1: no padding.
    EXPECT_EQ(bytes.size(), cdr ? 4u + 8 + 4 + 9 + 3 + 37 * 8 : 12u + 4 + 8 + 37 * 8);
    ImuMessage m;
    (cdr ? decodeImuCdr : decodeImuRos1)(bytes, "bag.db3", 0, m);
    EXPECT_EQ(m.stamp_ns, 3000000007);
    EXPECT_EQ(m.frame_id, "imu_link");
    EXPECT_EQ(m.orientation, (std::array<double, 4>{0.1, -0.2, 0.3, 0.927}));
    EXPECT_EQ(m.angular_velocity, (std::array<double, 3>{0.5, -1.5, 2.5}));
    EXPECT_EQ(m.linear_acceleration, (std::array<double, 3>{0.25, 0.125, 9.75}));
    EXPECT_TRUE(m.hasOrientation());
    expectEveryCutRefused<ImuMessage>(bytes, cdr ? decodeImuCdr : decodeImuRos1);
  }
  sample.orientation_covariance0 = -1.0;  // the message's "no orientation"
  ImuMessage m;
  decodeImuCdr(test::cdrImu(sample), "bag.db3", 0, m);
  EXPECT_FALSE(m.hasOrientation());
}

TEST(RosMessages, AWrenchStampedDecodesInBothEncodings) {
  test::WrenchSample sample;
  sample.stamp_ns = 12000000345;
  sample.frame = "ft";
  sample.force << 1.5, -2.5, 30.0;
  sample.torque << -0.5, 0.75, 0.0625;
  for (bool cdr : {true, false}) {
    const std::string bytes = cdr ? test::cdrWrench(sample) : test::ros1Wrench(sample);
    WrenchStampedMessage m;
    (cdr ? decodeWrenchStampedCdr : decodeWrenchStampedRos1)(bytes, "bag.db3", 0, m);
    EXPECT_EQ(m.stamp_ns, 12000000345);
    EXPECT_EQ(m.frame_id, "ft");
    EXPECT_EQ(m.force, (std::array<double, 3>{1.5, -2.5, 30.0}));
    EXPECT_EQ(m.torque, (std::array<double, 3>{-0.5, 0.75, 0.0625}));
    expectEveryCutRefused<WrenchStampedMessage>(
        bytes, cdr ? decodeWrenchStampedCdr : decodeWrenchStampedRos1);
  }
  std::string other = test::cdrWrench(sample);
  other[1] = 0x03;  // PL_CDR_LE
  WrenchStampedMessage m;
  EXPECT_THROW(decodeWrenchStampedCdr(other, "bag.db3", 0, m), ParseError);
}

TEST(RosMessages, ABoolDecodesInBothEncodingsAndIsZeroOrOne) {
  // CDR: the encapsulation header (little-endian CDR), then the byte; ROS 1: the byte alone.
  const std::string cdr_true("\x00\x01\x00\x00\x01", 5), cdr_false("\x00\x01\x00\x00\x00", 5);
  EXPECT_TRUE(decodeBoolCdr(cdr_true, "bag.db3", 0));
  EXPECT_FALSE(decodeBoolCdr(cdr_false, "bag.db3", 0));
  EXPECT_TRUE(decodeBoolRos1(std::string("\x01", 1), "bag.bag", 0));
  EXPECT_FALSE(decodeBoolRos1(std::string("\x00", 1), "bag.bag", 0));
  EXPECT_THROW(decodeBoolCdr(cdr_true.substr(0, 4), "bag.db3", 0), ParseError);  // no byte
  EXPECT_THROW(decodeBoolRos1("", "bag.bag", 0), ParseError);
  try {
    decodeBoolRos1(std::string("\x02", 1), "bag.bag", 40);
    ADD_FAILURE() << "a Bool of 2 was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("0 or 1, not 2"), std::string::npos) << e.what();
  }
  std::string other = cdr_true;
  other[1] = 0x03;  // PL_CDR_LE
  EXPECT_THROW(decodeBoolCdr(other, "bag.db3", 0), ParseError);
}

}  // namespace
}  // namespace dynid::bags
