#include "data/floating/floating_log.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/floating/floating_columns.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {
using namespace floating_columns;

/// A sensor's columns (in its values' order) and what its samples are called in messages.
struct SignalColumns {
  std::string what;
  std::vector<int> columns;
  FloatingLogSignal* signal = nullptr;
};

/// The header's columns, checked against the model.
class LogHeader {
 public:
  LogHeader(const std::string& file, const FloatingModel& model, std::vector<std::string> names)
      : file_(file), model_(model), names_(std::move(names)) {
    const int n = model.numJoints();
    for (const std::string& j : model.limbs().joint_names) joints_.push_back(j);
    for (const BodyFrame& f : model.frames) frames_.push_back(f.name);
    for (int b = 0; b < 3; ++b) joint_cols_[b].assign(static_cast<std::size_t>(n), -1);
    imu_cols_.fill(-1);
    for (std::size_t c = 0; c < names_.size(); ++c) classify(static_cast<int>(c));
  }

  /// The sensors' column lists into `out`'s signals (after the checks of completeness).
  std::vector<SignalColumns> signals(FloatingLogTable& out) {
    if (time_ < 0) throw ParseError(file_, 1, "t", "no time column: a floating log needs t [s]");
    std::vector<SignalColumns> result;
    SignalColumns joints{"the joints", {}, &out.joints};
    for (int b = 0; b < 3; ++b) {
      const auto& cols = joint_cols_[b];
      const auto given = std::count_if(cols.begin(), cols.end(), [](int c) { return c >= 0; });
      if (given == 0 && b > 0) continue;
      for (std::size_t j = 0; j < cols.size(); ++j)
        if (cols[j] < 0)
          throw ParseError(file_, 1, std::string(kJointBlocks[b == 2 ? 3 : b]) + ":" + joints_[j],
                           "no column for joint '" + joints_[j] + "'" +
                               (b == 0 ? "" : ": give every joint's or none"));
      joints.columns.insert(joints.columns.end(), cols.begin(), cols.end());
    }
    out.has_dq = joint_cols_[1][0] >= 0;
    out.has_tau = joint_cols_[2][0] >= 0;
    out.joints.width = static_cast<int>(joints.columns.size());
    result.push_back(joints);
    for (int k = 0; k < 10; ++k)
      if (imu_cols_[static_cast<std::size_t>(k)] < 0)
        throw ParseError(file_, 1,
                         k < 4
                             ? "base:" + std::string(kOrientation[k])
                             : "imu:" + (imu_frame_.empty() ? "F" : imu_frame_) + ":" + kImu[k - 4],
                         "a floating log gives the base's motion by its orientation (base:qw .. "
                         "base:qz) and an IMU on the base body (imu:F:wx .. imu:F:az): this "
                         "column is missing");
    out.imu.frame = imu_frame_;
    out.imu.width = 10;
    result.push_back({"the IMU", {imu_cols_.begin(), imu_cols_.end()}, &out.imu});
    out.wrenches.resize(wrench_order_.size());
    for (std::size_t w = 0; w < wrench_order_.size(); ++w) {
      const std::string& frame = wrench_order_[w];
      const std::array<int, 6>& cols = wrench_cols_.at(frame);
      for (int r = 3; r < 6; ++r)
        if (cols[static_cast<std::size_t>(r)] < 0)
          throw ParseError(file_, 1, "wrench:" + frame + ":" + kWrench[r],
                           "a wrench needs fx, fy and fz");
      const int moments = static_cast<int>(
          std::count_if(cols.begin(), cols.begin() + 3, [](int c) { return c >= 0; }));
      if (moments != 0 && moments != 3)
        throw ParseError(file_, 1, "wrench:" + frame + ":nx", "a wrench's moment needs nx, ny, nz");
      out.wrenches[w].frame = frame;
      out.wrenches[w].width = moments == 3 ? 6 : 3;
      result.push_back({"the wrench at '" + frame + "'",
                        {cols.begin() + (moments == 3 ? 0 : 3), cols.end()},
                        &out.wrenches[w]});
    }
    out.flags.resize(flag_order_.size());
    for (std::size_t f = 0; f < flag_order_.size(); ++f) {
      out.flags[f].frame = flag_order_[f];
      out.flags[f].width = 1;
      result.push_back({"the flag at '" + flag_order_[f] + "'", {flag_cols_[f]}, &out.flags[f]});
    }
    return result;
  }
  int time() const { return time_; }

 private:
  [[noreturn]] void fail(int c, const std::string& message) const {
    throw ParseError(file_, 1, names_[static_cast<std::size_t>(c)], message);
  }
  void once(int& slot, int c) {
    if (slot >= 0) fail(c, "a second '" + names_[static_cast<std::size_t>(c)] + "' column");
    slot = c;
  }
  std::string frameOf(int c, const std::string& frame) const {
    if (model_.findFrame(frame) == nullptr)
      fail(c, "'" + frame + "' is no frame of '" + model_.name() +
                  "'; its frames: " + listed(frames_));
    return frame;
  }
  void classify(int c) {
    const std::string& name = names_[static_cast<std::size_t>(c)];
    if (name == "t") return once(time_, c);
    const std::size_t colon = name.find(':');
    const std::string kind = name.substr(0, colon),
                      rest = colon == std::string::npos ? "" : name.substr(colon + 1);
    const std::size_t last = rest.rfind(':');
    const std::string frame = rest.substr(0, last),
                      component = last == std::string::npos ? "" : rest.substr(last + 1);
    if (kind == "q" || kind == "dq" || kind == "tau") {
      const auto j = std::find(joints_.begin(), joints_.end(), rest);
      if (j == joints_.end())
        fail(c, "'" + rest + "' is no joint of '" + model_.name() +
                    "'; its joints: " + listed(joints_));
      const int block = kind == "q" ? 0 : kind == "dq" ? 1 : 2;
      return once(joint_cols_[block][static_cast<std::size_t>(j - joints_.begin())], c);
    }
    if (kind == "ddq")
      fail(c, "ddq is what a preparation derives: a raw log gives q (and dq when logged)");
    if (kind == "base") {
      const int k = indexOf(kOrientation, 4, rest);
      if (k < 0)
        fail(c,
             "a raw log's base columns are its orientation (base:qw .. base:qz); its twist "
             "comes from the IMU (a table with base:wx .. columns is a prepared dataset, read "
             "as a dataset)");
      return once(imu_cols_[static_cast<std::size_t>(k)], c);
    }
    if (kind == "imu") {
      const int k = indexOf(kImu, 6, component);
      if (k < 0) fail(c, "an IMU column is imu:FRAME:wx (wy, wz, ax, ay, az)");
      const BodyFrame* f = model_.findFrame(frameOf(c, frame));
      if (f->body != -1)
        fail(c, "the IMU's frame '" + frame + "' is on a limb: only an IMU on the base body ('" +
                    model_.baseName() + "') gives the base's motion");
      if (!imu_frame_.empty() && imu_frame_ != frame)
        fail(c, "a second IMU ('" + imu_frame_ + "' and '" + frame + "'): give one");
      imu_frame_ = frame;
      return once(imu_cols_[static_cast<std::size_t>(4 + k)], c);
    }
    if (kind == "wrench") {
      const int k = indexOf(kWrench, 6, component);
      if (k < 0) fail(c, "a wrench column is wrench:FRAME:fx (fy, fz, nx, ny, nz)");
      frameOf(c, frame);
      if (!wrench_cols_.count(frame)) {
        wrench_cols_[frame].fill(-1);
        wrench_order_.push_back(frame);
      }
      return once(wrench_cols_[frame][static_cast<std::size_t>(k)], c);
    }
    if (kind == "contact") {
      frameOf(c, rest);
      if (std::find(flag_order_.begin(), flag_order_.end(), rest) != flag_order_.end())
        fail(c, "a second 'contact:" + rest + "' column");
      flag_order_.push_back(rest);
      flag_cols_.push_back(c);
      return;
    }
    fail(c,
         "unknown column: a floating log has t, q:J, dq:J, tau:J, base:qw .. base:qz, "
         "imu:F:wx .., wrench:F:fx .. and contact:F columns (docs/FLOATING.md)");
  }

  const std::string& file_;
  const FloatingModel& model_;
  std::vector<std::string> names_, joints_, frames_;
  int time_ = -1;
  std::array<std::vector<int>, 3> joint_cols_;
  std::array<int, 10> imu_cols_{};
  std::string imu_frame_;
  std::map<std::string, std::array<int, 6>> wrench_cols_;
  std::vector<std::string> wrench_order_, flag_order_;
  std::vector<int> flag_cols_;
};

/// One row's sample of a sensor, when its fields are all there: none empty adds it, all empty
/// skips it, some empty is an error naming the first.
void addSample(const SignalColumns& s, const std::vector<std::string_view>& fields,
               const std::vector<std::string>& names, double time, const std::string& file,
               int line, bool flag) {
  int empty = 0, first_empty = -1;
  for (int c : s.columns)
    if (trim(fields[static_cast<std::size_t>(c)]).empty()) {
      if (first_empty < 0) first_empty = c;
      ++empty;
    }
  if (empty == static_cast<int>(s.columns.size())) return;
  if (empty > 0)
    throw ParseError(file, line, names[static_cast<std::size_t>(first_empty)],
                     "empty while " + s.what +
                         " has other fields in this row: a sensor's sample is all of its "
                         "fields or none");
  for (int c : s.columns) {
    const double x = parseField(fields[static_cast<std::size_t>(c)], file, line,
                                names[static_cast<std::size_t>(c)]);
    if (flag && x != 0.0 && x != 1.0)
      throw ParseError(file, line, names[static_cast<std::size_t>(c)],
                       "a contact flag is 0 or 1, not " +
                           std::string(trim(fields[static_cast<std::size_t>(c)])));
    s.signal->values.push_back(x);
  }
  s.signal->time.push_back(time);
  s.signal->lines.push_back(line);
}
}  // namespace

FloatingLogTable readFloatingLogTable(const std::string& path, const FloatingModel& model) {
  FloatingLogTable out;
  out.file = path;
  ColumnTable table(path, "a floating log");
  const std::vector<std::string>& names = table.names();
  LogHeader header(path, model, names);
  const std::vector<SignalColumns> signals = header.signals(out);
  const std::size_t flags_from = signals.size() - out.flags.size();
  int rows = 0;
  std::vector<std::string_view> fields;
  while (table.next(fields)) {
    const int at = table.line();
    const double t = parseField(fields[static_cast<std::size_t>(header.time())], path, at, "t");
    for (std::size_t s = 0; s < signals.size(); ++s)
      addSample(signals[s], fields, names, t, path, at, s >= flags_from);
    // The orientation of an IMU sample in this row: unit, as a dataset's (normalised within
    // kQuaternionNormTolerance of it by the preparation).
    if (!out.imu.lines.empty() && out.imu.lines.back() == at) {
      const double* q = out.imu.values.data() + out.imu.values.size() - 10;
      const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance))
        throw ParseError(path, at, "base:qw",
                         "the base orientation (base:qw, base:qx, base:qy, base:qz) has norm " +
                             formatNumber(norm, 6) + ": not a unit quaternion");
    }
    ++rows;
  }
  if (rows == 0) throw ParseError(path, 2, "", "no sample: the file has a header and no row");
  return out;
}

}  // namespace dynid
