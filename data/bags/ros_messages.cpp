#include "data/bags/ros_messages.hpp"

#include <bit>
#include <cstring>

#include "data/bags/bytes.hpp"

namespace dynid::bags {

namespace {

/// Reads CDR fields of either byte order, aligned from the payload's start (after the 4-byte
/// encapsulation header), as XCDR1 specifies.
class CdrReader {
 public:
  CdrReader(Cursor& c, bool big_endian) : c_(c), big_(big_endian), origin_(c.position()) {}
  template <class T>
  T get(const char* field) {
    c_.align(sizeof(T), origin_, field);
    T value = c_.get<T>(field);
    if (big_) value = swapped(value);
    return value;
  }
  std::uint32_t count(const char* field, std::size_t element) {
    const auto n = get<std::uint32_t>(field);
    // Each element takes at least `element` bytes: a count beyond the bytes left is damage, and
    // refusing it here bounds every allocation by the message's size.
    if (element > 0 && n > c_.remaining() / element)
      c_.fail(field, "an array of " + std::to_string(n) + " elements in " +
                         std::to_string(c_.remaining()) + " bytes");
    return n;
  }
  std::string string(const char* field) {
    const std::uint32_t n = count(field, 1);
    const std::string_view s = c_.bytes(n, field);
    if (n == 0 || s.back() != '\0') c_.fail(field, "a string without its terminating NUL");
    return std::string(s.substr(0, n - 1));
  }
  /// std_msgs/Header: the stamp [ns], and the frame_id into `frame` (when not null).
  std::int64_t header(std::string* frame) {
    const auto sec = get<std::int32_t>("header.stamp.sec");
    const auto nanosec = get<std::uint32_t>("header.stamp.nanosec");
    std::string frame_id = string("header.frame_id");
    if (frame) *frame = std::move(frame_id);
    return static_cast<std::int64_t>(sec) * 1000000000 + nanosec;
  }
  template <std::size_t N>
  void fixed(std::array<double, N>& out, const char* field) {  // float64[N]: no length
    for (double& x : out) x = get<double>(field);
  }
  std::vector<double> doubles(const char* field) {
    const std::uint32_t n = count(field, 8);
    std::vector<double> out(n);
    if (n > 0) c_.align(8, origin_, field);
    for (double& x : out) x = get<double>(field);
    return out;
  }

 private:
  template <class T>
  static T swapped(T value) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    std::memcpy(&value, b, sizeof(T));
    return value;
  }
  Cursor& c_;
  bool big_;
  std::size_t origin_;
};

/// The encapsulation header: plain CDR of either byte order, else a ParseError naming `type`.
CdrReader openCdr(Cursor& c, const char* type) {
  const auto kind = c.get<std::uint16_t>("encapsulation");
  c.get<std::uint16_t>("encapsulation options");
  // The kind is big-endian on the wire: 0x0000 CDR_BE, 0x0001 CDR_LE (read here byte-swapped).
  if (kind != 0x0000 && kind != 0x0100)
    c.fail("encapsulation", "not plain CDR (kind 0x" +
                                std::to_string(((kind & 0xff) << 8) | (kind >> 8)) + "): " + type +
                                " is read from CDR only");
  return CdrReader(c, kind == 0x0000);
}

/// std_msgs/Header in ROS 1 (seq, stamp, frame_id).
std::int64_t ros1Header(Cursor& c, std::string* frame) {
  c.get<std::uint32_t>("header.seq");
  const auto sec = c.get<std::uint32_t>("header.stamp.secs");
  const auto nsec = c.get<std::uint32_t>("header.stamp.nsecs");
  const std::string_view frame_id = c.string("header.frame_id");
  if (frame) *frame = std::string(frame_id);
  return static_cast<std::int64_t>(sec) * 1000000000 + nsec;
}

/// ROS 1's fields through the calls CdrReader offers (no alignment, no encapsulation).
class Ros1Reader {
 public:
  explicit Ros1Reader(Cursor& c) : c_(c) {}
  std::int64_t header(std::string* frame) { return ros1Header(c_, frame); }
  template <std::size_t N>
  void fixed(std::array<double, N>& out, const char* field) {
    for (double& x : out) x = c_.get<double>(field);
  }

 private:
  Cursor& c_;
};

/// sensor_msgs/Imu's fields, in either encoding's reader.
template <class Reader>
void imuFields(Reader& r, ImuMessage& out) {
  out.stamp_ns = r.header(&out.frame_id);
  r.fixed(out.orientation, "orientation");
  r.fixed(out.orientation_covariance, "orientation_covariance");
  r.fixed(out.angular_velocity, "angular_velocity");
  std::array<double, 9> skipped;
  r.fixed(skipped, "angular_velocity_covariance");
  r.fixed(out.linear_acceleration, "linear_acceleration");
  r.fixed(skipped, "linear_acceleration_covariance");
}

/// geometry_msgs/WrenchStamped's fields, in either encoding's reader.
template <class Reader>
void wrenchFields(Reader& r, WrenchStampedMessage& out) {
  out.stamp_ns = r.header(&out.frame_id);
  r.fixed(out.force, "wrench.force");
  r.fixed(out.torque, "wrench.torque");
}

}  // namespace

void decodeJointStateCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                         JointStateMessage& out) {
  Cursor c(bytes, file, base);
  CdrReader r = openCdr(c, "JointState");
  out.stamp_ns = r.header(nullptr);
  const std::uint32_t names = r.count("name", 5);  // a length and a NUL at least
  out.name.resize(names);
  for (std::string& n : out.name) n = r.string("name");
  out.position = r.doubles("position");
  out.velocity = r.doubles("velocity");
  out.effort = r.doubles("effort");
}

void decodeJointStateRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                          JointStateMessage& out) {
  Cursor c(bytes, file, base);
  out.stamp_ns = ros1Header(c, nullptr);
  const auto names = c.get<std::uint32_t>("name");
  if (names > c.remaining() / 4) c.fail("name", "more names than the bytes left hold");
  out.name.resize(names);
  for (std::string& n : out.name) n = std::string(c.string("name"));
  for (auto [field, target] :
       {std::pair{"position", &out.position}, std::pair{"velocity", &out.velocity},
        std::pair{"effort", &out.effort}}) {
    const auto n = c.get<std::uint32_t>(field);
    if (n > c.remaining() / 8) c.fail(field, "more values than the bytes left hold");
    target->resize(n);
    for (double& x : *target) x = c.get<double>(field);
  }
}

void decodeImuCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                  ImuMessage& out) {
  Cursor c(bytes, file, base);
  CdrReader r = openCdr(c, "Imu");
  imuFields(r, out);
}

void decodeImuRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                   ImuMessage& out) {
  Cursor c(bytes, file, base);
  Ros1Reader r(c);
  imuFields(r, out);
}

void decodeWrenchStampedCdr(std::string_view bytes, const std::string& file, std::uint64_t base,
                            WrenchStampedMessage& out) {
  Cursor c(bytes, file, base);
  CdrReader r = openCdr(c, "WrenchStamped");
  wrenchFields(r, out);
}

void decodeWrenchStampedRos1(std::string_view bytes, const std::string& file, std::uint64_t base,
                             WrenchStampedMessage& out) {
  Cursor c(bytes, file, base);
  Ros1Reader r(c);
  wrenchFields(r, out);
}

namespace {
bool boolValue(Cursor& c) {
  const auto value = c.get<std::uint8_t>("data");
  if (value > 1) c.fail("data", "a Bool is 0 or 1, not " + std::to_string(value));
  return value == 1;
}
}  // namespace

bool decodeBoolCdr(std::string_view bytes, const std::string& file, std::uint64_t base) {
  Cursor c(bytes, file, base);
  openCdr(c, "Bool");
  return boolValue(c);
}

bool decodeBoolRos1(std::string_view bytes, const std::string& file, std::uint64_t base) {
  Cursor c(bytes, file, base);
  return boolValue(c);
}

}  // namespace dynid::bags
