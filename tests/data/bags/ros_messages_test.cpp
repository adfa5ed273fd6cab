// The JointState decoders: a ROS 2 CDR message laid out by hand from the XCDR1 rules (a 4-byte
// encapsulation header, each field aligned to its size from the payload's start), decoded field
// by field; every truncation of it refused with the file and byte offset. (Messages from ROS's own
// serializers come with the bag fixtures of the log import.)
#include "data/bags/ros_messages.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"

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

}  // namespace
}  // namespace dynid::bags
