// Robot recordings (ROS 2 bags: .mcap, .db3 or their directory; ROS 1 .bag) as RawSignals: the
// sensor_msgs/JointState messages of one topic, joints matched by name to the robot's, in any
// order (others ignored), stamped by their header or by their receive time.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "analysis/logs/read_log.hpp"

namespace dynid {

/// What scanJointStates found: the topic read, the joint names (the robot's, or the first
/// message's), whether the messages carry velocities, and how many there were.
struct JointStateScan {
  std::string topic;
  std::vector<std::string> names;
  bool has_dq = false;
  long long messages = 0;
  /// The prefix every one of the robot's joint names carries in the messages ("panda_" for
  /// "panda_joint1" as "joint1"; empty: the names themselves): a warning for the reader to give.
  std::string prefix;
  /// The prefix every one of the robot's joint names carries and the messages' lack
  /// ("lbr_" for "lbr_iiwa_joint_1" as "iiwa_joint_1"), likewise.
  std::string robot_prefix;
};

/// Receives each message: its stamp [ns on the recording's clock] and the joints' values in
/// `names` order: q (n), tau (n; zeros when the efforts come from another topic or table), then
/// dq (n) when the messages carry velocities.
using JointStateVisit = std::function<void(std::int64_t stamp_ns, const std::vector<double>& row)>;

/// Visits the JointState messages of `source`'s topic in `path` in the recording's order, one at a
/// time (constant memory); the efforts of source.effort_topic or effort_table are not joined here
/// (readBagLog does). Throws as readBagLog, the checks that need every message (no message,
/// several topics, no header stamp) after the last one.
JointStateScan scanJointStates(const LogSource& source, const std::string& path,
                               const JointStateVisit& visit);

/// The warning for scan.prefix or scan.robot_prefix: the robot's joints were found under that
/// prefix, or without it ("" when the names matched as they are).
std::string prefixWarning(const JointStateScan& scan);

/// Reads the recording `path` for `source` (its topic, joint names and stamp). Throws InputError
/// naming the recording and what is wrong: no JointState topic, several without --topic, joints
/// of the robot the messages lack (and the names they hold), no effort, header stamps that are
/// all zero (use the receive time); ParseError for a damaged file (file and byte offset).
/// With `scratch_dir` and the efforts in the messages, the samples go to a scratch file there as
/// they are read (RawSignals::spilled: memory independent of the recording's length).
RawSignals readBagLog(const LogSource& source, const std::string& path,
                      const std::string& scratch_dir = "");

}  // namespace dynid
