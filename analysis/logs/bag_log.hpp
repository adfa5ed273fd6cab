// Robot recordings (ROS 2 bags: .mcap, .db3 or their directory; ROS 1 .bag) as RawSignals: the
// sensor_msgs/JointState messages of one topic, joints matched by name to the robot's, in any
// order (others ignored), stamped by their header or by their receive time.
#pragma once

#include <string>
#include <vector>

#include "analysis/logs/read_log.hpp"

namespace dynid {

/// Reads the recording `path` for `source` (its topic, joint names and stamp). Throws InputError
/// naming the recording and what is wrong: no JointState topic, several without --topic, joints
/// of the robot the messages lack (and the names they hold), no effort, header stamps that are
/// all zero (use the receive time); ParseError for a damaged file (file and byte offset).
RawSignals readBagLog(const LogSource& source, const std::string& path);

}  // namespace dynid
