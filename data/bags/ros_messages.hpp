// The one message type identification needs, sensor_msgs/JointState, decoded from what bags hold:
// ROS 2's CDR (XCDR1, either byte order, as rosbag2 and MCAP store it) and ROS 1's serialization.
// A small reader of these fields rather than Debian's libfastcdr: the layout is four fields long,
// and a generic CDR library would still need the type written out by hand (no IDL here).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dynid::bags {

struct JointStateMessage {
  std::int64_t stamp_ns = 0;  // header.stamp [ns since its epoch]
  std::vector<std::string> name;
  std::vector<double> position, velocity, effort;  // each empty or one per name
};

/// The schema names a JointState is stored under (ROS 2, ROS 1).
inline constexpr std::string_view kJointStateRos2 = "sensor_msgs/msg/JointState";
inline constexpr std::string_view kJointStateRos1 = "sensor_msgs/JointState";

/// Decodes a ROS 2 CDR JointState (4-byte encapsulation header, then the fields). Throws
/// ParseError naming `file`, the field and the byte offset `base` + its position for a truncated
/// or inconsistent message (an array longer than the bytes left, a string without its NUL, an
/// encapsulation other than CDR).
void decodeJointStateCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                         JointStateMessage& out);

/// Decodes a ROS 1 JointState (header seq, stamp, frame_id; then the arrays). Errors as above.
void decodeJointStateRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                          JointStateMessage& out);

}  // namespace dynid::bags
