#include "data/floating/floating_dataset.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <map>
#include <string_view>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/floating/floating_columns.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {
using namespace floating_columns;

/// Where a column's values go.
struct Target {
  enum Kind { kTime, kOrientation, kTwist, kAcceleration, kJoint, kWrench, kFlag, kImu };
  Kind kind = kTime;
  int block = 0;  // joint columns: q, dq, ddq, tau
  int index = 0;  // the component, joint, wrench or flag
  int row = 0;    // a wrench's component row (0..5; a point's force is 3..5 until it is known)
};

/// The header's columns, checked against the model: what each column holds.
class HeaderReader {
 public:
  HeaderReader(const std::string& file, const FloatingModel& model, FloatingDataset& out)
      : file_(file), model_(model), out_(out) {
    out_.joints = model.limbs().joint_names;
    for (const BodyFrame& f : model.frames) frames_.push_back(f.name);
  }

  std::vector<Target> read(const std::vector<std::string_view>& header) {
    std::vector<Target> targets;
    std::map<std::string, int> seen;
    for (std::size_t c = 0; c < header.size(); ++c) {
      const std::string name(trim(header[c]));
      if (!seen.emplace(name, static_cast<int>(c)).second)
        fail(c, name, "the column '" + name + "' appears twice");
      targets.push_back(target(c, name));
    }
    checkComplete(seen);
    return targets;
  }

  /// Per wrench (wrenches' order): which of its six components (kWrench's order) have columns.
  std::vector<std::array<bool, 6>> wrench_components;

 private:
  [[noreturn]] void fail(std::size_t c, const std::string& name, const std::string& why) const {
    throw ParseError(file_, 1, name.empty() ? "column " + std::to_string(c + 1) : name, why);
  }

  Target target(std::size_t c, const std::string& name) {
    if (name == "t") return {};
    const std::size_t colon = name.find(':');
    const std::string kind = name.substr(0, colon),
                      rest = colon == std::string::npos ? std::string() : name.substr(colon + 1);
    if (kind == "base") {
      if (int k = indexOf(kOrientation, 4, rest); k >= 0) return {Target::kOrientation, 0, k};
      if (int k = indexOf(kTwist, 6, rest); k >= 0) return {Target::kTwist, 0, k};
      if (int k = indexOf(kAcceleration, 6, rest); k >= 0) return {Target::kAcceleration, 0, k};
      fail(c, name,
           "unknown base column '" + name +
               "'; the base's are base:qw..qz, base:wx..vz "
               "(twist) and base:dwx..dvz (its derivative)");
    }
    if (const int block = indexOf(kJointBlocks, 4, kind); block >= 0) {
      const auto& joints = out_.joints;
      for (std::size_t j = 0; j < joints.size(); ++j)
        if (joints[j] == rest) return {Target::kJoint, block, static_cast<int>(j)};
      fail(c, name,
           "'" + rest + "' is no joint of '" + model_.name() + "'; its joints: " + listed(joints));
    }
    if (kind == "imu") return imuTarget(c, name, rest);
    if (kind == "wrench" || kind == "contact") {
      std::string frame = rest, component;
      if (kind == "wrench") {
        const std::size_t last = rest.rfind(':');
        if (last == std::string::npos)
          fail(c, name, "a wrench column is wrench:FRAME:fx (fy, fz, nx, ny, nz)");
        frame = rest.substr(0, last);
        component = rest.substr(last + 1);
      }
      if (model_.findFrame(frame) == nullptr)
        fail(c, name,
             "'" + frame + "' is no frame of '" + model_.name() + "' (a " + kind +
                 " in an unknown frame); its frames: " + listed(frames_));
      if (kind == "contact") {
        out_.flags.push_back({frame, {}});
        return {Target::kFlag, 0, static_cast<int>(out_.flags.size() - 1)};
      }
      const int row = indexOf(kWrench, 6, component);
      if (row < 0)
        fail(c, name, "unknown wrench component '" + component + "' (fx, fy, fz, nx, ny, nz)");
      int w = 0;
      while (w < static_cast<int>(out_.wrenches.size()) && out_.wrenches[w].frame != frame) ++w;
      if (w == static_cast<int>(out_.wrenches.size())) {
        out_.wrenches.push_back({frame, {}});
        wrench_components.push_back({});
      }
      wrench_components[static_cast<std::size_t>(w)][static_cast<std::size_t>(row)] = true;
      return {Target::kWrench, 0, w, row};
    }
    fail(c, name,
         "unknown column '" + name +
             "'; a floating dataset has t, base:..., q:J, dq:J, "
             "ddq:J, tau:J, wrench:F:fx.., contact:F and imu:F:wx.. columns (docs/FLOATING.md)");
  }

  /// imu:F:wx .. az: one IMU, on the base body.
  Target imuTarget(std::size_t c, const std::string& name, const std::string& rest) {
    const std::size_t last = rest.rfind(':');
    const std::string frame = last == std::string::npos ? rest : rest.substr(0, last);
    const int k = last == std::string::npos ? -1 : indexOf(kImu, 6, rest.substr(last + 1));
    if (k < 0)
      fail(c, name,
           "an IMU column is imu:FRAME:wx (wy, wz: the gyro; ax, ay, az: the "
           "accelerometer)");
    const BodyFrame* f = model_.findFrame(frame);
    if (f == nullptr)
      fail(c, name,
           "'" + frame + "' is no frame of '" + model_.name() +
               "' (an IMU in an unknown frame); "
               "its frames: " +
               listed(frames_));
    if (f->body >= 0)
      fail(c, name,
           "the IMU's frame '" + frame + "' is on a limb: only an IMU on the base body ('" +
               model_.baseName() + "' or a link fixed to it) gives the base's motion");
    if (!out_.imu_frame.empty() && out_.imu_frame != frame)
      fail(c, name, "a second IMU ('" + out_.imu_frame + "' and '" + frame + "'): give one");
    out_.imu_frame = frame;
    return {Target::kImu, 0, k};
  }

  void checkComplete(const std::map<std::string, int>& seen) const {
    const auto require = [&](const std::string& name) {
      if (!seen.count(name))
        throw ParseError(file_, 1, name, "the header lacks the column '" + name + "'");
    };
    require("t");
    for (const char* k : kOrientation) require(std::string("base:") + k);
    if (out_.imu_frame.empty()) {
      for (const char* k : kTwist) require(std::string("base:") + k);
      for (const char* k : kAcceleration) require(std::string("base:") + k);
    } else {
      for (const char* k : kImu) require("imu:" + out_.imu_frame + ":" + k);
      for (const auto& [name, column] : seen)
        if (name.rfind("base:", 0) == 0 && indexOf(kOrientation, 4, name.substr(5)) < 0)
          throw ParseError(file_, 1, name,
                           "the base's motion from base: columns and from an IMU: give one");
    }
    for (int block = 0; block < 3; ++block)
      for (const std::string& j : out_.joints) require(std::string(kJointBlocks[block]) + ":" + j);
    bool any_tau = false;
    for (const std::string& j : out_.joints) any_tau = any_tau || seen.count("tau:" + j);
    if (any_tau)
      for (const std::string& j : out_.joints) require("tau:" + j);
    for (std::size_t w = 0; w < out_.wrenches.size(); ++w) {
      const auto& has = wrench_components[w];
      const std::string prefix = "wrench:" + out_.wrenches[w].frame + ":";
      for (int r = 3; r < 6; ++r) require(prefix + kWrench[r]);
      if (has[0] || has[1] || has[2])
        for (int r = 0; r < 3; ++r) require(prefix + kWrench[r]);
    }
  }

  const std::string& file_;
  const FloatingModel& model_;
  FloatingDataset& out_;
  std::vector<std::string> frames_;
};

}  // namespace

const FloatingDataset::Wrench* FloatingDataset::findWrench(const std::string& frame) const {
  for (const Wrench& w : wrenches)
    if (w.frame == frame) return &w;
  return nullptr;
}

const FloatingDataset::Flag* FloatingDataset::findFlag(const std::string& frame) const {
  for (const Flag& f : flags)
    if (f.frame == frame) return &f;
  return nullptr;
}

std::string floatingDatasetHeader(const FloatingDataset& d) {
  // Appended piece by piece (GCC 12 warns falsely of overlapping copies in a + b + c here).
  std::string out = "t";
  const auto column = [&out](std::initializer_list<std::string_view> parts) {
    out.append(",");
    for (std::string_view p : parts) out.append(p);
  };
  for (const char* k : kOrientation) column({"base:", k});
  for (const char* k : kTwist) column({"base:", k});
  for (const char* k : kAcceleration) column({"base:", k});
  for (int block = 0; block < (d.hasTorques() ? 4 : 3); ++block)
    for (const std::string& j : d.joints) column({kJointBlocks[block], ":", j});
  for (const FloatingDataset::Wrench& w : d.wrenches)
    for (int r = w.values.rows() == 6 ? 0 : 3; r < 6; ++r)
      column({"wrench:", w.frame, ":", kWrench[r]});
  for (const FloatingDataset::Flag& f : d.flags) column({"contact:", f.frame});
  return out;
}

void writeFloatingDataset(const std::string& path, const FloatingDataset& dataset) {
  AtomicWriter out(path);
  writeFloatingDataset(out, dataset);
  out.commit();
}

void writeFloatingDataset(AtomicWriter& out, const FloatingDataset& d) {
  const Eigen::Index N = d.time.size(), n = static_cast<Eigen::Index>(d.joints.size());
  bool ok = d.orientation.cols() == N && d.twist.cols() == N && d.acceleration.cols() == N &&
            d.q.rows() == n && d.q.cols() == N && d.dq.rows() == n && d.dq.cols() == N &&
            d.ddq.rows() == n && d.ddq.cols() == N &&
            (d.tau.rows() == 0 || (d.tau.rows() == n && d.tau.cols() == N));
  for (const auto& w : d.wrenches)
    ok = ok && (w.values.rows() == 3 || w.values.rows() == 6) && w.values.cols() == N;
  for (const auto& f : d.flags) ok = ok && static_cast<Eigen::Index>(f.holding.size()) == N;
  if (!ok) throw InputError("a floating dataset's signals disagree in size");
  out.write(floatingDatasetHeader(d) + "\n");
  std::string row;
  for (Eigen::Index k = 0; k < N; ++k) {
    row = formatNumber(d.time[k]);
    const auto add = [&](double x) {
      row += ',';
      row += formatNumber(x);
    };
    for (int r = 0; r < 4; ++r) add(d.orientation(r, k));
    for (int r = 0; r < 6; ++r) add(d.twist(r, k));
    for (int r = 0; r < 6; ++r) add(d.acceleration(r, k));
    for (const Eigen::MatrixXd* m : {&d.q, &d.dq, &d.ddq, &d.tau})
      for (Eigen::Index j = 0; j < m->rows(); ++j) add((*m)(j, k));
    for (const auto& w : d.wrenches)
      for (Eigen::Index r = 0; r < w.values.rows(); ++r) add(w.values(r, k));
    for (const auto& f : d.flags) row += f.holding[static_cast<std::size_t>(k)] ? ",1" : ",0";
    row += '\n';
    out.write(row);
  }
}

namespace {
/// The dataset's signals sized for N samples of the header's columns.
void sizeSignals(FloatingDataset& out, const std::vector<Target>& targets,
                 const std::vector<std::array<bool, 6>>& wrench_components, Eigen::Index N) {
  const Eigen::Index n = static_cast<Eigen::Index>(out.joints.size());
  out.time.resize(N);
  out.orientation.resize(4, N);
  out.twist.resize(6, N);
  out.acceleration.resize(6, N);
  for (Eigen::MatrixXd* m : {&out.q, &out.dq, &out.ddq}) m->resize(n, N);
  bool torques = false;
  for (const Target& t : targets) torques = torques || (t.kind == Target::kJoint && t.block == 3);
  out.tau.resize(torques ? n : 0, N);
  for (std::size_t w = 0; w < out.wrenches.size(); ++w)
    out.wrenches[w].values.resize(wrench_components[w][0] ? 6 : 3, N);
  for (auto& f : out.flags) f.holding.resize(static_cast<std::size_t>(N));
}

/// Sample k's values (one per column) into the dataset, the IMU's into `imu`; its flags, time
/// order and quaternion checked.
void assignRow(FloatingDataset& out, const std::vector<Target>& targets,
               const std::vector<std::string>& names, const double* row, Eigen::Index k,
               Eigen::Matrix<double, 6, Eigen::Dynamic>& imu) {
  const int file_line = out.line(static_cast<int>(k));
  for (std::size_t c = 0; c < targets.size(); ++c) {
    const Target& t = targets[c];
    const double x = row[c];
    switch (t.kind) {
      case Target::kTime:
        out.time[k] = x;
        break;
      case Target::kOrientation:
        out.orientation(t.index, k) = x;
        break;
      case Target::kTwist:
        out.twist(t.index, k) = x;
        break;
      case Target::kAcceleration:
        out.acceleration(t.index, k) = x;
        break;
      case Target::kImu:
        imu(t.index, k) = x;
        break;
      case Target::kJoint: {
        Eigen::MatrixXd* m[] = {&out.q, &out.dq, &out.ddq, &out.tau};
        (*m[t.block])(t.index, k) = x;
        break;
      }
      case Target::kWrench: {
        Eigen::MatrixXd& v = out.wrenches[static_cast<std::size_t>(t.index)].values;
        v(v.rows() == 6 ? t.row : t.row - 3, k) = x;
        break;
      }
      case Target::kFlag:
        if (x != 0.0 && x != 1.0)
          throw ParseError(out.file, file_line, names[c],
                           "a contact flag is 0 or 1, not " + formatNumber(x));
        out.flags[static_cast<std::size_t>(t.index)].holding[static_cast<std::size_t>(k)] =
            x != 0.0;
        break;
    }
  }
  if (k > 0 && !(out.time[k] > out.time[k - 1]))
    throw ParseError(out.file, file_line, "t",
                     "time " + formatNumber(out.time[k]) + " does not increase (the row before: " +
                         formatNumber(out.time[k - 1]) + ")");
  const double norm = out.orientation.col(k).norm();
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance))
    throw ParseError(out.file, file_line, "base:qw",
                     "the base orientation (base:qw, base:qx, base:qy, base:qz) has norm " +
                         formatNumber(norm, 6) + "; a unit quaternion is within " +
                         formatNumber(kQuaternionNormTolerance) + " of 1");
  out.orientation.col(k) /= norm;
}

/// The base's twist and its derivative from the IMU's signals (floating_dataset.hpp's rule).
void baseMotionFromImu(const FloatingModel& model, FloatingDataset& d,
                       const Eigen::Matrix<double, 6, Eigen::Dynamic>& imu) {
  const Eigen::Index N = d.time.size();
  if (N < 2)
    throw ParseError(d.file, d.line(0), "imu:" + d.imu_frame + ":wx",
                     "one sample: the base's angular acceleration from an IMU needs two or more");
  const Pose<double>& F = model.findFrame(d.imu_frame)->placement;
  for (Eigen::Index k = 0; k < N; ++k) {
    Eigen::Vector3d dgyro;
    if (k == 0 || k == N - 1) {  // one-sided
      const Eigen::Index a = k == 0 ? 0 : N - 2;
      dgyro = (imu.col(a + 1).head<3>() - imu.col(a).head<3>()) / (d.time[a + 1] - d.time[a]);
    } else {  // the derivative at t_k of the parabola through the three samples
      const double h1 = d.time[k] - d.time[k - 1], h2 = d.time[k + 1] - d.time[k];
      dgyro = -h2 / (h1 * (h1 + h2)) * imu.col(k - 1).head<3>() +
              (h2 - h1) / (h1 * h2) * imu.col(k).head<3>() +
              h1 / (h2 * (h1 + h2)) * imu.col(k + 1).head<3>();
    }
    const Eigen::Matrix3d R = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    imuBaseMotion(model, F, R, imu.col(k).head<3>(), dgyro, imu.col(k).tail<3>(), d.twist.col(k),
                  d.acceleration.col(k));
  }
}
}  // namespace

void imuBaseMotion(const FloatingModel& model, const Pose<double>& imu,
                   const Eigen::Matrix3d& rotation, const Eigen::Vector3d& gyro,
                   const Eigen::Vector3d& dgyro, const Eigen::Vector3d& specific_force,
                   Eigen::Ref<Vector6<double>> twist, Eigen::Ref<Vector6<double>> acceleration) {
  const Eigen::Vector3d omega = imu.rotation * gyro, alpha = imu.rotation * dgyro;
  const Eigen::Vector3d& r = imu.translation;
  // The IMU point's acceleration in base axes, then the base origin's.
  const Eigen::Vector3d at_imu =
      imu.rotation * specific_force + rotation.transpose() * model.gravity();
  twist << omega, Eigen::Vector3d::Zero();
  acceleration << alpha, at_imu - alpha.cross(r) - omega.cross(omega.cross(r));
}

FloatingDataset readFloatingDataset(const std::string& path, const FloatingModel& model) {
  FloatingDataset out;
  out.file = path;
  ColumnTable table(path, "a floating dataset");
  HeaderReader header_reader(path, model, out);
  const std::vector<std::string>& names = table.names();
  const std::vector<Target> targets = header_reader.read(table.headerFields());
  const std::size_t columns = targets.size();
  std::vector<double> values;
  std::vector<std::string_view> fields;
  while (table.next(fields)) {
    for (std::size_t c = 0; c < columns; ++c)
      values.push_back(parseField(fields[c], path, table.line(), names[c]));
    out.lines.push_back(table.line());
  }
  const Eigen::Index N = static_cast<Eigen::Index>(out.lines.size());
  if (N == 0) throw ParseError(path, 2, "", "no sample: the file has a header and no row");
  sizeSignals(out, targets, header_reader.wrench_components, N);
  Eigen::Matrix<double, 6, Eigen::Dynamic> imu(6, out.imu_frame.empty() ? 0 : N);
  for (Eigen::Index k = 0; k < N; ++k)
    assignRow(out, targets, names, values.data() + k * static_cast<Eigen::Index>(columns), k, imu);
  if (!out.imu_frame.empty()) baseMotionFromImu(model, out, imu);
  return out;
}

}  // namespace dynid
