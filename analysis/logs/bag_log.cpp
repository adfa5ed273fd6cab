#include "analysis/logs/bag_log.hpp"

#include <algorithm>

#include "core/errors.hpp"
#include "data/bags/bag.hpp"
#include "data/bags/ros_messages.hpp"

namespace dynid {

namespace {

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

/// Per joint of `names` (the robot's), its entry among the message's names `held`; InputError
/// naming the joints the messages lack and the names they hold.
std::vector<int> jointIndex(const std::vector<std::string>& names,
                            const std::vector<std::string>& held, const std::string& path,
                            const std::string& topic) {
  std::vector<int> index(names.size(), -1);
  std::vector<std::string> missing;
  for (std::size_t j = 0; j < names.size(); ++j) {
    const auto it = std::find(held.begin(), held.end(), names[j]);
    if (it == held.end())
      missing.push_back(names[j]);
    else
      index[j] = static_cast<int>(it - held.begin());
  }
  if (!missing.empty())
    throw InputError(path + ": the JointState messages on " + topic + " lack the robot's joints " +
                     listed(missing) + " (they hold " + listed(held) +
                     "): give the robot these messages describe");
  return index;
}

/// A position and an effort per name, or the error that says which is missing and where.
void checkArrays(const bags::JointStateMessage& m, const bags::BagMessage& message,
                 const std::string& path, const std::string& topic) {
  const std::size_t held = m.name.size();
  if (m.position.size() != held)
    throw ParseError(*message.file, 0, "position",
                     "at byte " + std::to_string(message.offset) + ": " +
                         std::to_string(m.position.size()) + " positions for " +
                         std::to_string(held) + " names");
  if (m.effort.size() != held)
    throw InputError(
        path + ": the JointState messages on " + topic +
        (m.effort.empty() ? " carry no effort (torque)" : " carry efforts for only some joints") +
        ": dynid needs the measured torques (at byte " + std::to_string(message.offset) + " of " +
        *message.file + ")");
}

}  // namespace

RawSignals readBagLog(const LogSource& source, const std::string& path) {
  RawSignals out;
  out.file = path;
  out.tau_file = path;
  std::string topic = source.topic;
  std::vector<std::string> names = source.joint_names;  // the robot's; empty: the first message's
  std::vector<std::string> other_topics;
  std::vector<std::string> last_names;
  std::vector<int> index;  // per joint: its entry in the message
  std::vector<double> rows;
  std::int64_t first_ns = 0;
  bool first = true, any_header_stamp = false;
  bags::JointStateMessage m;
  Eigen::Index count = 0;
  bags::readBag(
      path,
      source.topic.empty() ? std::vector<std::string>{} : std::vector<std::string>{source.topic},
      [&](const bags::BagMessage& message) {
        if (message.type != bags::kJointStateRos2 && message.type != bags::kJointStateRos1) {
          if (!source.topic.empty())
            throw InputError(*message.file + ": topic " + source.topic + " holds " +
                             std::string(message.type) + " messages, not sensor_msgs/JointState");
          return;
        }
        if (topic.empty()) topic = std::string(message.topic);
        if (message.topic != topic) {
          if (std::find(other_topics.begin(), other_topics.end(), message.topic) ==
              other_topics.end())
            other_topics.emplace_back(message.topic);
          return;
        }
        if (message.encoding == bags::Encoding::kCdr)
          bags::decodeJointStateCdr(message.data, *message.file, message.offset, m);
        else
          bags::decodeJointStateRos1(message.data, *message.file, message.offset, m);
        if (m.name != last_names) {  // the mapping, again only when the names change
          if (names.empty()) names = m.name;
          index = jointIndex(names, m.name, path, topic);
          last_names = m.name;
        }
        checkArrays(m, message, path, topic);
        const std::size_t held = m.name.size();
        const bool velocity = m.velocity.size() == held;
        if (first) out.has_dq = velocity;
        if (out.has_dq != velocity)
          throw InputError(path + ": some JointState messages on " + topic +
                           " carry velocities and some do not");
        const std::int64_t stamp = source.receive_time ? message.receive_ns : m.stamp_ns;
        any_header_stamp = any_header_stamp || m.stamp_ns != 0;
        if (first) first_ns = stamp;
        first = false;
        // The difference of integer nanoseconds, then seconds: exact to the double's precision.
        rows.push_back(static_cast<double>(stamp - first_ns) * 1e-9);
        for (int j : index) rows.push_back(m.position[static_cast<std::size_t>(j)]);
        for (int j : index) rows.push_back(m.effort[static_cast<std::size_t>(j)]);
        if (out.has_dq)
          for (int j : index) rows.push_back(m.velocity[static_cast<std::size_t>(j)]);
        ++count;
      });
  if (count == 0)
    throw InputError(path + ": no sensor_msgs/JointState messages" +
                     (source.topic.empty() ? std::string() : " on " + source.topic));
  if (!other_topics.empty())
    throw InputError(path + ": JointState messages on several topics (" + topic + ", " +
                     listed(other_topics) + "): give --topic");
  if (!source.receive_time && !any_header_stamp)
    throw InputError(path +
                     ": every JointState header stamp is zero (the publisher does not "
                     "stamp them): give --stamp receive");
  const auto n = static_cast<int>(names.size());
  const int width = 1 + (out.has_dq ? 3 : 2) * n;
  out.values =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          rows.data(), count, width);
  out.n = n;
  out.rows = count;
  out.ddq_at = width;
  out.time_origin = static_cast<long double>(first_ns) / 1e9L;  // seconds, the unit of bags
  out.columns.time = source.receive_time ? "receive time" : "header.stamp";
  out.columns.q = names;
  out.columns.tau = names;
  if (out.has_dq) out.columns.dq = names;
  return out;
}

}  // namespace dynid
