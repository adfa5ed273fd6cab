#include "analysis/logs/bag_log.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "analysis/logs/raw_log.hpp"
#include "core/errors.hpp"
#include "data/bags/bag.hpp"
#include "data/bags/ros_messages.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

/// bags::readBag, its files remembered as the command's inputs (the documents' provenance).
void readRecording(const std::string& path, const std::vector<std::string>& topics,
                   const std::function<void(const bags::BagMessage&)>& on_message) {
  for (const std::string& file : bags::bagFiles(path)) noteInputFile(file);
  bags::readBag(path, topics, on_message);
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

/// The prefixes P = h - `name` of the names h among `longer` that end in `name` after a
/// separator ("panda_" for "panda_joint1" and "joint1"), kept where `fits_every_joint(P)`.
template <class Fits>
std::vector<std::string> prefixesThatFit(const std::vector<std::string>& longer,
                                         const std::string& name, Fits fits_every_joint) {
  std::vector<std::string> fits;
  for (const std::string& h : longer) {
    if (h.size() <= name.size() || h.compare(h.size() - name.size(), name.size(), name) != 0 ||
        std::string_view("_/:-.").find(h[h.size() - name.size() - 1]) == std::string_view::npos)
      continue;
    const std::string p = h.substr(0, h.size() - name.size());
    if (fits_every_joint(p)) fits.push_back(p);
  }
  return fits;
}

/// Per joint of `names` (the robot's), its entry among the message's names `held`: the same name,
/// else, when no name is missing that way, one prefix that every joint's name carries after a
/// separator ("panda_joint1" for "joint1": a driver's prefix), recorded in `prefix` (a gripper's
/// "panda_finger_joint1" is no match: "panda_finger_joint2..7" are missing); else one prefix every
/// one of the robot's names carries and the messages' lack ("lbr_iiwa_joint_1" as
/// "iiwa_joint_1": a description generated with a prefix), recorded in `robot_prefix`. InputError
/// naming the joints the messages lack (and the names they hold), or the prefixes that fit alike.
std::vector<int> jointIndex(const std::vector<std::string>& names,
                            const std::vector<std::string>& held, const std::string& path,
                            const std::string& topic, std::string* prefix = nullptr,
                            std::string* robot_prefix = nullptr) {
  const auto find = [&](const std::string& name) {
    return static_cast<int>(std::find(held.begin(), held.end(), name) - held.begin());
  };
  std::vector<int> index(names.size(), -1);
  std::vector<std::string> missing;
  for (std::size_t j = 0; j < names.size(); ++j) {
    index[j] = find(names[j]);
    if (index[j] == static_cast<int>(held.size())) missing.push_back(names[j]);
  }
  if (missing.empty() || names.empty()) return index;
  const auto all_held = [&](const std::string& p) {
    return std::all_of(names.begin(), names.end(), [&](const std::string& name) {
      return find(p + name) < static_cast<int>(held.size());
    });
  };
  // Prefixes P with P + name held for every joint.
  std::vector<std::string> fits = prefixesThatFit(held, names.front(), all_held);
  if (fits.empty()) {
    // Prefixes P that every robot name starts with, the rest of each held.
    std::vector<std::string> robot_fits;
    for (const std::string& h : held) {
      const auto rest_held = [&](const std::string& p) {
        return std::all_of(names.begin(), names.end(), [&](const std::string& name) {
          return name.size() > p.size() && name.compare(0, p.size(), p) == 0 &&
                 find(name.substr(p.size())) < static_cast<int>(held.size());
        });
      };
      for (const std::string& p : prefixesThatFit({names.front()}, h, rest_held))
        if (std::find(robot_fits.begin(), robot_fits.end(), p) == robot_fits.end())
          robot_fits.push_back(p);
    }
    if (robot_fits.size() == 1) {
      const std::string& p = robot_fits.front();
      for (std::size_t j = 0; j < names.size(); ++j) index[j] = find(names[j].substr(p.size()));
      if (robot_prefix != nullptr) *robot_prefix = p;
      return index;
    }
  }
  if (fits.size() > 1)
    throw InputError(path + ": the JointState messages on " + topic +
                     " name the robot's joints under several prefixes (" + listed(fits) +
                     "): say which arm with `joint_prefix` " + fits.front() + " (or another)");
  if (fits.empty())
    throw InputError(path + ": the JointState messages on " + topic + " lack the robot's joints " +
                     listed(missing) + " (they hold " + listed(held) +
                     "): give the robot these messages describe");
  for (std::size_t j = 0; j < names.size(); ++j) index[j] = find(fits.front() + names[j]);
  if (prefix != nullptr) *prefix = fits.front();
  return index;
}

/// A position and an effort per name, or the error that says which is missing and where.
void checkArrays(const bags::JointStateMessage& m, const bags::BagMessage& message,
                 const std::string& path, const std::string& topic, bool need_effort) {
  const std::size_t held = m.name.size();
  if (m.position.size() != held)
    throw ParseError(*message.file, 0, "position",
                     "at byte " + std::to_string(message.offset) + ": " +
                         std::to_string(m.position.size()) + " positions for " +
                         std::to_string(held) + " names");
  if (need_effort && m.effort.size() != held)
    throw InputError(
        path + ": the JointState messages on " + topic +
        (m.effort.empty() ? " carry no effort (torque)" : " carry efforts for only some joints") +
        ": dynid needs the measured torques (at byte " + std::to_string(message.offset) + " of " +
        *message.file +
        "); a second topic or a table may give them (`effort_topic`, "
        "`effort_log`)");
}

/// Efforts from a second source, at its own stamps (ns on the recording's clock), n per stamp.
struct EffortSamples {
  std::vector<std::int64_t> ns;
  std::vector<double> values;  // row-major
  std::vector<std::string> columns;
};

/// The JointState efforts on `topic` of the recording, matched by name to `names`.
EffortSamples effortTopic(const LogSource& source, const std::string& path,
                          const std::vector<std::string>& names) {
  EffortSamples e;
  const std::string& topic = source.effort_topic;
  bags::JointStateMessage m;
  std::vector<std::string> last_names;
  std::vector<int> index;
  readRecording(path, {topic}, [&](const bags::BagMessage& message) {
    if (message.type != bags::kJointStateRos2 && message.type != bags::kJointStateRos1)
      throw InputError(*message.file + ": topic " + topic + " holds " + std::string(message.type) +
                       " messages, not sensor_msgs/JointState");
    if (message.encoding == bags::Encoding::kCdr)
      bags::decodeJointStateCdr(message.data, *message.file, message.offset, m);
    else
      bags::decodeJointStateRos1(message.data, *message.file, message.offset, m);
    if (m.name != last_names) {
      index = jointIndex(names, m.name, path, topic);
      last_names = m.name;
    }
    if (m.effort.size() != m.name.size())
      throw InputError(path + ": the JointState messages on " + topic +
                       " carry no effort for every name (at byte " +
                       std::to_string(message.offset) + " of " + *message.file + ")");
    e.ns.push_back(source.receive_time ? message.receive_ns : m.stamp_ns);
    for (int j : index) e.values.push_back(m.effort[static_cast<std::size_t>(j)]);
  });
  if (e.ns.empty()) throw InputError(path + ": no messages on `effort_topic` " + topic);
  for (const std::string& name : names) e.columns.push_back(topic + ": " + name);
  return e;
}

/// The torque (or current) columns of the table source.effort_table, against its time column
/// (seconds on the recording's clock, e.g. epoch seconds beside header stamps).
EffortSamples effortTable(const LogSource& source, int n) {
  const RawTable header = readRawHeader(source.effort_table, source.decimal_comma);
  std::vector<int> columns = selectColumns(header, source.time_column, 1, "`time_column`");
  const std::vector<int> tau =
      selectColumns(header, source.tau_columns, n, source.current ? "`current`" : "`tau_columns`");
  columns.insert(columns.end(), tau.begin(), tau.end());
  long double origin = 0.0L;
  const Eigen::MatrixXd v = readRawColumns(header, columns, &origin);
  EffortSamples e;
  for (Eigen::Index r = 0; r < v.rows(); ++r) {
    e.ns.push_back(std::llround((origin + static_cast<long double>(v(r, 0))) * 1e9L));
    for (int j = 0; j < n; ++j) e.values.push_back(v(r, 1 + j));
  }
  for (int c : tau) e.columns.push_back(header.names[static_cast<std::size_t>(c)]);
  return e;
}

/// Each row's torque interpolated linearly in time between the effort samples around its stamp
/// (the measurement's own values where a stamp coincides); rows outside the samples' span are
/// dropped. Returns how many were.
Eigen::Index joinEfforts(EffortSamples e, const std::vector<std::int64_t>& stamps, int n, int width,
                         std::vector<double>& rows) {
  std::vector<std::size_t> order(e.ns.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return e.ns[a] < e.ns[b]; });
  std::vector<std::int64_t> ns(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) ns[i] = e.ns[order[i]];
  const auto value = [&](std::size_t i, int j) {
    return e.values[order[i] * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
  };
  std::size_t kept = 0;
  for (std::size_t k = 0; k < stamps.size(); ++k) {
    const auto after = std::lower_bound(ns.begin(), ns.end(), stamps[k]);
    if (after == ns.end()) continue;
    const auto hi = static_cast<std::size_t>(after - ns.begin());
    if (ns[hi] != stamps[k] && hi == 0) continue;
    double* row = rows.data() + k * static_cast<std::size_t>(width);
    for (int j = 0; j < n; ++j) {
      if (ns[hi] == stamps[k]) {
        row[1 + n + j] = value(hi, j);
      } else {
        const double w =
            static_cast<double>(stamps[k] - ns[hi - 1]) / static_cast<double>(ns[hi] - ns[hi - 1]);
        row[1 + n + j] = (1.0 - w) * value(hi - 1, j) + w * value(hi, j);
      }
    }
    std::copy(row, row + width, rows.data() + kept * static_cast<std::size_t>(width));
    ++kept;
  }
  rows.resize(kept * static_cast<std::size_t>(width));
  return static_cast<Eigen::Index>(stamps.size() - kept);
}

/// The efforts of source.effort_topic or source.effort_table joined into `rows` (the position
/// samples at `stamps`, `width` values each) for the robot's joints `names`; records the source in
/// `out` and a warning for dropped samples. Returns the rows left; InputError when fewer than 2.
Eigen::Index joinSeparateEfforts(const LogSource& source, const std::string& path,
                                 const std::vector<std::string>& names,
                                 const std::vector<std::int64_t>& stamps, int width,
                                 std::vector<double>& rows, RawSignals& out) {
  const auto n = static_cast<int>(names.size());
  const EffortSamples effort =
      source.effort_table.empty() ? effortTopic(source, path, names) : effortTable(source, n);
  const Eigen::Index dropped = joinEfforts(effort, stamps, n, width, rows);
  const auto count = static_cast<Eigen::Index>(stamps.size()) - dropped;
  if (count < 2)
    throw InputError(path + ": the efforts (" +
                     (source.effort_table.empty() ? source.effort_topic : source.effort_table) +
                     ") do not span the positions' stamps: are both on the same clock (" +
                     (source.receive_time ? "receive time" : "header stamps") + ")?");
  if (dropped > 0)
    out.warnings.push_back(std::to_string(dropped) +
                           " position samples outside the efforts' time span were dropped");
  out.tau_file = source.effort_table.empty() ? path : source.effort_table;
  out.columns.tau = effort.columns;
  return count;
}

}  // namespace

std::string prefixWarning(const JointStateScan& scan) {
  const std::string more = scan.names.size() > 1 ? ", ..." : "";
  if (!scan.robot_prefix.empty())
    return "the robot's joint names carry the prefix '" + scan.robot_prefix +
           "' the messages lack (" + scan.names.front() + " as " +
           scan.names.front().substr(scan.robot_prefix.size()) + more + "): matched so";
  if (scan.prefix.empty()) return "";
  return "the messages name the robot's joints with the prefix '" + scan.prefix + "' (" +
         scan.prefix + scan.names.front() + " as " + scan.names.front() + more + "): matched so";
}

JointStateScan scanJointStates(const LogSource& source, const std::string& path,
                               const JointStateVisit& visit) {
  JointStateScan scan;
  scan.topic = source.topic;
  scan.names = source.joint_names;  // the robot's; empty: the first message's
  if (!source.joint_prefix.empty()) {
    if (scan.names.empty())
      throw InputError(path +
                       ": `joint_prefix` names the robot's joints in the messages: give "
                       "the robot (`robot`)");
    for (std::string& name : scan.names) name = source.joint_prefix + name;
  }
  std::string& topic = scan.topic;
  std::vector<std::string>& names = scan.names;
  std::vector<std::string> other_topics;
  std::vector<std::string> last_names;
  std::vector<int> index;  // per joint: its entry in the message
  std::vector<double> row;
  bool first = true, any_header_stamp = false;
  bags::JointStateMessage m;
  const bool separate_effort = !source.effort_topic.empty() || !source.effort_table.empty();
  if (!source.effort_topic.empty() && source.effort_topic == source.topic)
    throw InputError(path + ": the effort topic is the position topic " + topic +
                     ": give the topic whose JointState messages carry the efforts");
  readRecording(
      path,
      source.topic.empty() ? std::vector<std::string>{} : std::vector<std::string>{source.topic},
      [&](const bags::BagMessage& message) {
        if (message.type != bags::kJointStateRos2 && message.type != bags::kJointStateRos1) {
          if (!source.topic.empty())
            throw InputError(*message.file + ": topic " + source.topic + " holds " +
                             std::string(message.type) + " messages, not sensor_msgs/JointState");
          return;
        }
        if (message.topic == source.effort_topic) return;  // read on its own (effortTopic)
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
          index = jointIndex(names, m.name, path, topic, &scan.prefix, &scan.robot_prefix);
          last_names = m.name;
        }
        checkArrays(m, message, path, topic, !separate_effort);
        const std::size_t held = m.name.size();
        const bool velocity = m.velocity.size() == held;
        if (first) scan.has_dq = velocity;
        if (scan.has_dq != velocity)
          throw InputError(path + ": some JointState messages on " + topic +
                           " carry velocities and some do not");
        first = false;
        any_header_stamp = any_header_stamp || m.stamp_ns != 0;
        row.clear();
        for (int j : index) row.push_back(m.position[static_cast<std::size_t>(j)]);
        for (int j : index)
          row.push_back(separate_effort ? 0.0 : m.effort[static_cast<std::size_t>(j)]);
        if (scan.has_dq)
          for (int j : index) row.push_back(m.velocity[static_cast<std::size_t>(j)]);
        ++scan.messages;
        visit(source.receive_time ? message.receive_ns : m.stamp_ns, row);
      });
  if (scan.messages == 0)
    throw InputError(path + ": no sensor_msgs/JointState messages" +
                     (source.topic.empty() ? std::string() : " on " + source.topic));
  if (!other_topics.empty())
    throw InputError(path + ": JointState messages on several topics (" + topic + ", " +
                     listed(other_topics) + "): give `topic`");
  if (!source.receive_time && !any_header_stamp)
    throw InputError(path +
                     ": every JointState header stamp is zero (the publisher does not "
                     "stamp them): give `stamp` receive");
  return scan;
}

RawSignals readBagLog(const LogSource& source, const std::string& path,
                      const std::string& scratch_dir) {
  RawSignals out;
  out.file = path;
  out.tau_file = path;
  // The rows (time, then the visit's values) in blocks of kBlockRows: nothing read is moved again
  // while the recording is read, and each block goes into the column-major matrix while it is
  // still in cache, freed once copied (a row-major copy of the whole log, then its transpose,
  // took a third of the time of preparing an hour-long bag and twice its memory).
  constexpr std::size_t kBlockRows = 4096;
  std::vector<std::vector<double>> blocks;
  std::size_t total = 0, width = 0;
  std::vector<std::int64_t> stamps;  // every row's, on the recording's clock [ns] (joins only)
  std::int64_t first_ns = 0;
  const bool separate_effort = !source.effort_topic.empty() || !source.effort_table.empty();
  // With a scratch directory: the time in memory, every other column written to the scratch file
  // a block at a time (the block's rows, column by column).
  const bool spill = !scratch_dir.empty() && !separate_effort;
  std::vector<double> times, column;
  const auto spillBlock = [&] {
    std::vector<double>& block = blocks.back();
    const std::size_t held = block.size() / width, first = times.size();
    column.resize(held);
    for (std::size_t c = 0; c < width; ++c) {
      for (std::size_t k = 0; k < held; ++k) column[k] = block[k * width + c];
      if (c == 0)
        times.insert(times.end(), column.begin(), column.end());
      else
        out.spilled->write(static_cast<int>(c) - 1, static_cast<std::int64_t>(first), column.data(),
                           static_cast<std::int64_t>(held));
    }
    block.clear();
  };
  const JointStateScan scan =
      scanJointStates(source, path, [&](std::int64_t ns, const std::vector<double>& row) {
        if (total == 0) {
          first_ns = ns;
          width = 1 + row.size();
          if (spill)
            out.spilled =
                std::make_shared<ScratchColumns>(scratch_dir, static_cast<int>(row.size()));
        }
        if (spill && !blocks.empty() && blocks.back().size() == kBlockRows * width) spillBlock();
        if (blocks.empty() || (!spill && blocks.back().size() == kBlockRows * width)) {
          blocks.emplace_back();
          blocks.back().reserve(kBlockRows * width);
        }
        std::vector<double>& block = blocks.back();
        // The difference of integer nanoseconds, then seconds: exact to the double's precision.
        block.push_back(static_cast<double>(ns - first_ns) * 1e-9);
        block.insert(block.end(), row.begin(), row.end());
        if (separate_effort) stamps.push_back(ns);
        ++total;
      });
  const auto n = static_cast<int>(scan.names.size());
  out.has_dq = scan.has_dq;
  if (const std::string w = prefixWarning(scan); !w.empty()) out.warnings.push_back(w);
  auto count = static_cast<Eigen::Index>(total);
  const auto columns = static_cast<Eigen::Index>(width);
  if (spill) {
    if (!blocks.empty()) spillBlock();
    out.values = Eigen::Map<const Eigen::VectorXd>(times.data(), count);
  } else if (separate_effort) {
    std::vector<double> rows;
    rows.reserve(total * width);
    for (std::vector<double>& block : blocks) {
      rows.insert(rows.end(), block.begin(), block.end());
      std::vector<double>().swap(block);
    }
    count =
        joinSeparateEfforts(source, path, scan.names, stamps, static_cast<int>(width), rows, out);
    out.values =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            rows.data(), count, columns);
  } else {
    out.values.resize(count, columns);
    Eigen::Index first = 0;
    for (std::vector<double>& block : blocks) {
      const auto held = static_cast<Eigen::Index>(block.size() / width);
      out.values.middleRows(first, held) =
          Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
              block.data(), held, columns);
      first += held;
      std::vector<double>().swap(block);
    }
  }
  out.ddq_at = static_cast<int>(width);
  out.n = n;
  out.rows = count;
  out.time_origin = static_cast<long double>(first_ns) / 1e9L;  // seconds, the unit of bags
  out.columns.time = source.receive_time ? "receive time" : "header.stamp";
  out.columns.q = scan.names;
  if (!separate_effort) out.columns.tau = scan.names;
  if (out.has_dq) out.columns.dq = scan.names;
  return out;
}

}  // namespace dynid
