// Robot recordings in the containers ROS writes, one interface over them: so far a ROS 2 MCAP
// file (.mcap, data/bags/mcap.hpp) and a ROS 1 bag (.bag, format 2.0: data/bags/ros1_bag.hpp).
// Messages are handed over encoded, with their topic, type and encoding; decoding is the caller's
// (data/bags/ros_messages.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace dynid::bags {

enum class Encoding { kCdr, kRos1 };

struct BagMessage {
  std::string_view topic, type;  // e.g. /joint_states, sensor_msgs/msg/JointState
  Encoding encoding = Encoding::kCdr;
  std::int64_t receive_ns = 0;  // when the recorder received (logged) it [ns]
  std::string_view data;        // valid during the callback only
  const std::string* file = nullptr;
  std::uint64_t offset = 0;  // where it is in *file [bytes]
};

/// Whether `path` names a recording these readers take (by its extension: .mcap or .bag).
bool isBag(const std::string& path);

/// Calls `on_message` for every message on `topics` (all when empty) of the recording at `path`,
/// in file order. Throws ParseError naming the file and byte offset of damage, and InputError for
/// a path that is no recording.
void readBag(const std::string& path, const std::vector<std::string>& topics,
             const std::function<void(const BagMessage&)>& on_message);

}  // namespace dynid::bags
