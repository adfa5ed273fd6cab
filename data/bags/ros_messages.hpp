// The message types identification needs, decoded from what bags hold: sensor_msgs/JointState (a
// fixed-base arm's log), and for a floating base sensor_msgs/Imu and geometry_msgs/WrenchStamped;
// from ROS 2's CDR (XCDR1, either byte order, as rosbag2 and MCAP store it) and ROS 1's
// serialization. A small reader of these fields rather than Debian's libfastcdr: each layout is a
// header and a few arrays, and a generic CDR library would still need the types written out by
// hand (no IDL here).
#pragma once

#include <array>
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

/// sensor_msgs/Imu: the orientation of frame_id in its world (a quaternion x, y, z, w; unknown when
/// orientation_covariance[0] is -1, as the message's definition says), the gyro [rad/s] and the
/// accelerometer's specific force [m/s^2], both in frame_id's axes.
struct ImuMessage {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
  std::array<double, 4> orientation{};  // x, y, z, w
  std::array<double, 9> orientation_covariance{};
  std::array<double, 3> angular_velocity{}, linear_acceleration{};
  bool hasOrientation() const { return orientation_covariance[0] != -1.0; }
};

/// geometry_msgs/WrenchStamped: a force [N] and a torque [N m] in frame_id's axes.
struct WrenchStampedMessage {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
  std::array<double, 3> force{}, torque{};
};

inline constexpr std::string_view kImuRos2 = "sensor_msgs/msg/Imu";
inline constexpr std::string_view kImuRos1 = "sensor_msgs/Imu";
inline constexpr std::string_view kWrenchStampedRos2 = "geometry_msgs/msg/WrenchStamped";
inline constexpr std::string_view kWrenchStampedRos1 = "geometry_msgs/WrenchStamped";

/// std_msgs/Bool: one byte, 0 or 1 (a foot's contact switch). It has no header: its time is the
/// recorder's receive time.
inline constexpr std::string_view kBoolRos2 = "std_msgs/msg/Bool";
inline constexpr std::string_view kBoolRos1 = "std_msgs/Bool";

/// Decode a Bool, CDR (ROS 2) or ROS 1: ParseError for a message without its byte, a byte other
/// than 0 or 1, or not plain CDR; bytes after it are ignored.
bool decodeBoolCdr(std::string_view bytes, const std::string& file, std::uint64_t base);
bool decodeBoolRos1(std::string_view bytes, const std::string& file, std::uint64_t base);

/// Decode an Imu or a WrenchStamped, CDR (ROS 2) or ROS 1; errors as the JointState decoders'
/// (a message shorter than its fields, a frame_id without its NUL, not plain CDR). Bytes after the
/// last field are ignored (as ROS ignores them).
void decodeImuCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                  ImuMessage& out);
void decodeImuRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                   ImuMessage& out);
void decodeWrenchStampedCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                            WrenchStampedMessage& out);
void decodeWrenchStampedRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                             WrenchStampedMessage& out);

}  // namespace dynid::bags
