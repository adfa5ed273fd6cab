// Robot recordings in the containers ROS writes, one interface over all of them:
//   - ROS 2 (rosbag2): a bag directory whose metadata.yaml names its files in order (split bags),
//     or one file; each file SQLite (.db3, read with Debian's libsqlite3) or MCAP (.mcap, read by
//     data/bags/mcap.hpp);
//   - ROS 1: a .bag file (format 2.0; chunks uncompressed, bz2 or lz4: data/bags/ros1_bag.hpp).
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
  std::uint64_t offset = 0;  // where it is in *file [bytes] (.db3: its row id)
};

/// Whether `path` is a recording these readers take: a .db3, .mcap or .bag file (by its
/// extension), or a directory holding a metadata.yaml or .db3/.mcap files.
bool isBag(const std::string& path);

/// The files of a recording, in the order they are read: a directory's metadata.yaml
/// `relative_file_paths` (split bags; rosbag2 before metadata version 4 prefixed them with the
/// directory's name), else its .db3 and .mcap files in natural order (bag_2 before bag_10); a
/// file alone. Throws ParseError for a metadata.yaml naming a file outside the directory and
/// InputError for a directory with no recording in it.
std::vector<std::string> bagFiles(const std::string& path);

/// Calls `on_message` for every message on `topics` (all when empty) of the recording at `path`,
/// file after file (bagFiles), each in its own order: MCAP and ROS 1 in file order, SQLite by
/// receive time as rosbag2 plays it. Throws ParseError naming the file and the byte offset (.db3:
/// the row) of damage, and InputError for a path that is no recording.
void readBag(const std::string& path, const std::vector<std::string>& topics,
             const std::function<void(const BagMessage&)>& on_message);

}  // namespace dynid::bags
