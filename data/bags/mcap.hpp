// MCAP, the container ROS 2 records by default since Iron (`ros2 bag record`: .mcap), read from its
// specification (https://mcap.dev/spec, major version 0): the data section from start to end,
// chunks decompressed one at a time (none, zstd, lz4), their CRCs checked, the summary section
// (an index) not needed and not trusted. Debian has no MCAP library; this is ours, fuzzed
// (tests/fuzz/fuzz_mcap.cpp). Messages stay encoded: decoding them is the caller's (ROS 2 CDR in
// data/bags/ros_messages.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace dynid::bags {

class Cursor;  // data/bags/bytes.hpp

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding, data;  // e.g. sensor_msgs/msg/JointState, ros2msg, the .msg text
};

struct McapChannel {
  std::uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;  // e.g. /joint_states, cdr
};

/// A message as stored: its bytes are valid only during the callback.
struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0, publish_time = 0;  // [ns]
  std::string_view data;
  std::uint64_t offset = 0;  // the byte offset of its record (or of its chunk) in the file
};

/// The bounds a reader keeps to: a record or chunk above them is refused before any allocation.
inline constexpr std::uint64_t kMaxMcapRecord = std::uint64_t{1} << 31;  // 2 GiB

/// Reads `path` from start to end, calling `on_message` for every Message record in file order
/// (inside chunks too), with every Schema and Channel record met before it known to `schemas` and
/// `channels`. Unknown and private records are skipped, as the specification asks. Throws
/// ParseError naming the file and the byte offset for: a missing or wrong magic, a record or
/// field running past its end or the file's, a length above kMaxMcapRecord, an unknown
/// compression, a chunk whose CRC or uncompressed size does not match, a message on a channel
/// not defined before it, and a file that ends before its Data End record.
class McapReader {
 public:
  explicit McapReader(std::string path);
  void read(const std::function<void(const McapMessage&)>& on_message);
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }
  const std::string& profile() const { return profile_; }  // the Header's, e.g. ros2

 private:
  void handle(std::uint8_t op, std::uint64_t at, Cursor& record,
              const std::function<void(const McapMessage&)>& on_message);

  std::string path_;
  std::string profile_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
};

/// CRC-32 (IEEE 802.3, zlib's), which MCAP and ROS 2 use.
std::uint32_t crc32Of(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace dynid::bags
