#include "tests/common/floating_bag.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "core/floating/floating_rnea.hpp"
#include "tests/common/joint_state_db3.hpp"

namespace dynid::test {

namespace {

/// XCDR1 as ROS 2 writes it: a 4-byte encapsulation header (CDR, little endian), then each field
/// aligned to its size from the payload's start.
class Cdr {
 public:
  Cdr() : b_("\x00\x01\x00\x00", 4) {}
  template <class T>
  void put(T v) {
    while ((b_.size() - 4) % sizeof(T) != 0) b_.push_back('\0');
    b_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void header(std::int64_t stamp_ns, const std::string& frame) {
    put<std::int32_t>(static_cast<std::int32_t>(stamp_ns / 1000000000));
    put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns % 1000000000));
    put<std::uint32_t>(static_cast<std::uint32_t>(frame.size() + 1));
    b_.append(frame);
    b_.push_back('\0');
  }
  std::string b_;
};

/// ROS 1: little endian, no alignment, strings without their NUL.
class Ros1 {
 public:
  template <class T>
  void put(T v) {
    b_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void header(std::int64_t stamp_ns, const std::string& frame) {
    put<std::uint32_t>(7);  // seq
    put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns / 1000000000));
    put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns % 1000000000));
    put<std::uint32_t>(static_cast<std::uint32_t>(frame.size()));
    b_.append(frame);
  }
  std::string b_;
};

template <class Writer>
std::string imu(const ImuSample& m) {
  Writer w;
  w.header(m.stamp_ns, m.frame);
  for (int i = 0; i < 4; ++i) w.template put<double>(m.xyzw[i]);
  for (int i = 0; i < 9; ++i) w.template put<double>(i == 0 ? m.orientation_covariance0 : 0.0);
  for (int i = 0; i < 3; ++i) w.template put<double>(m.gyro[i]);
  for (int i = 0; i < 9; ++i) w.template put<double>(0.0);
  for (int i = 0; i < 3; ++i) w.template put<double>(m.accel[i]);
  for (int i = 0; i < 9; ++i) w.template put<double>(0.0);
  return w.b_;
}

template <class Writer>
std::string wrench(const WrenchSample& m) {
  Writer w;
  w.header(m.stamp_ns, m.frame);
  for (int i = 0; i < 3; ++i) w.template put<double>(m.force[i]);
  for (int i = 0; i < 3; ++i) w.template put<double>(m.torque[i]);
  return w.b_;
}

}  // namespace

std::string cdrImu(const ImuSample& m) { return imu<Cdr>(m); }
std::string ros1Imu(const ImuSample& m) { return imu<Ros1>(m); }
std::string cdrWrench(const WrenchSample& m) { return wrench<Cdr>(m); }
std::string ros1Wrench(const WrenchSample& m) { return wrench<Ros1>(m); }

SuspendedMotion::SuspendedMotion(const FloatingModel& model, std::uint64_t seed,
                                 bool support_moves) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto unit = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized(); };
  R0_ = Eigen::AngleAxisd(0.4 * u(rng), unit()).toRotationMatrix();
  axis_ = unit();
  angle_amplitude_ = 0.3 + 0.1 * u(rng);
  angle_frequency_ = 0.4 + 0.1 * u(rng);
  angle_phase_ = 3.0 * u(rng);
  for (int i = 0; i < 3; ++i) {
    p_amplitude_[i] = 0.05 + 0.02 * u(rng);
    p_frequency_[i] = 0.35 + 0.15 * u(rng);
    p_phase_[i] = 3.0 * u(rng);
  }
  if (!support_moves) {
    angle_amplitude_ = 0.0;
    p_amplitude_.setZero();
  }
  const int n = model.numJoints();
  q0_.resize(n);
  amplitude_.resize(n);
  frequency_.resize(n);
  phase_.resize(n);
  for (int j = 0; j < n; ++j) {
    q0_[j] = 0.2 * u(rng);
    amplitude_[j] = 0.4 + 0.1 * u(rng);
    frequency_[j] = 0.4 + 0.2 * u(rng);
    phase_[j] = 3.0 * u(rng);
  }
}

BaseMotion SuspendedMotion::base(double t) const {
  const double w = 2.0 * M_PI * angle_frequency_, s = std::sin(w * t + angle_phase_);
  const double angle = angle_amplitude_ * s;
  const double rate = angle_amplitude_ * w * std::cos(w * t + angle_phase_);
  const double acceleration = -angle_amplitude_ * w * w * s;
  BaseMotion out;
  out.rotation = R0_ * Eigen::AngleAxisd(angle, axis_).toRotationMatrix();
  Eigen::Vector3d p_dot, p_ddot;
  for (int i = 0; i < 3; ++i) {
    const double f = 2.0 * M_PI * p_frequency_[i];
    p_dot[i] = p_amplitude_[i] * f * std::cos(f * t + p_phase_[i]);
    p_ddot[i] = -p_amplitude_[i] * f * f * std::sin(f * t + p_phase_[i]);
  }
  // The axis is fixed in the base (and so in the world): omega and its derivative lie along it.
  const Eigen::Vector3d omega = rate * axis_, v = out.rotation.transpose() * p_dot;
  out.twist << omega, v;
  out.acceleration << acceleration * axis_, out.rotation.transpose() * p_ddot - omega.cross(v);
  return out;
}

Eigen::Vector3d SuspendedMotion::originAcceleration(double t) const {
  const BaseMotion b = base(t);
  return b.acceleration.tail<3>() + b.twist.head<3>().cross(b.twist.tail<3>());
}

Eigen::VectorXd SuspendedMotion::q(double t) const {
  const Eigen::ArrayXd w = 2.0 * M_PI * frequency_.array();
  return q0_.array() + amplitude_.array() * (w * t + phase_.array()).sin();
}
Eigen::VectorXd SuspendedMotion::dq(double t) const {
  const Eigen::ArrayXd w = 2.0 * M_PI * frequency_.array();
  return amplitude_.array() * w * (w * t + phase_.array()).cos();
}
Eigen::VectorXd SuspendedMotion::ddq(double t) const {
  const Eigen::ArrayXd w = 2.0 * M_PI * frequency_.array();
  return -amplitude_.array() * w * w * (w * t + phase_.array()).sin();
}

namespace {
/// Each sensor's samples of the motion (the joints', the IMU's, the sensor's), sensor by sensor,
/// each at its rate with its jittered stamps [ns, from 1 s].
struct SuspendedSink {
  std::function<void(std::int64_t, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                     const Eigen::VectorXd& tau)>
      joints;
  std::function<void(std::int64_t, const ImuSample&, const Eigen::Matrix3d& base_rotation)> imu;
  std::function<void(std::int64_t, const WrenchSample&)> wrench;
};

void suspendedSamples(const FloatingModel& model, const SuspendedMotion& motion,
                      const SuspendedRecordingOptions& options, const SuspendedSink& sink) {
  std::mt19937_64 rng(options.seed + 1000);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  FloatingData data(model);
  const Pose<double>& I = model.findFrame(options.imu_frame)->placement;
  const Pose<double>& S = model.findFrame(options.sensor_frame)->placement;
  const auto stamps = [&](double rate, double start, double end) {
    std::vector<std::int64_t> out;
    for (int k = 0; start + k / rate <= end; ++k)
      out.push_back(
          std::llround((start + (k + (k > 0 ? options.jitter * u(rng) : 0.0)) / rate) * 1e9) +
          1000000000);  // from 1 s: no negative stamps; the first one on time
    return out;
  };
  const auto time = [](std::int64_t ns) { return static_cast<double>(ns - 1000000000) * 1e-9; };
  const int n = model.numJoints();
  for (std::int64_t ns : stamps(options.joint_rate, options.joint_start, options.seconds)) {
    const double t = time(ns);
    const Eigen::VectorXd q = motion.q(t), dq = motion.dq(t);
    const Eigen::VectorXd& tau = floatingRnea(model, data, motion.base(t), q, dq, motion.ddq(t));
    sink.joints(ns, q, dq, tau.tail(n));
  }
  for (std::int64_t ns :
       stamps(options.imu_rate, 0.0, options.imu_end < 0.0 ? options.seconds : options.imu_end)) {
    const double t = time(ns);
    const BaseMotion b = motion.base(t);
    const Eigen::Vector3d omega = b.twist.head<3>(), alpha = b.acceleration.head<3>();
    const Eigen::Vector3d at_imu = motion.originAcceleration(t) + alpha.cross(I.translation) +
                                   omega.cross(omega.cross(I.translation));
    ImuSample m;
    m.stamp_ns = ns;
    m.frame = options.imu_frame;
    const Eigen::Quaterniond o(b.rotation * I.rotation);
    m.xyzw << o.x(), o.y(), o.z(), o.w();
    m.gyro = I.rotation.transpose() * omega;
    m.accel = I.rotation.transpose() * (at_imu - b.rotation.transpose() * model.gravity());
    m.orientation_covariance0 = options.orientation ? 0.0 : -1.0;
    sink.imu(ns, m, b.rotation);
  }
  for (std::int64_t ns : stamps(options.wrench_rate, 0.0, options.seconds)) {
    const double t = time(ns);
    const Eigen::VectorXd& w =
        floatingRnea(model, data, motion.base(t), motion.q(t), motion.dq(t), motion.ddq(t));
    WrenchSample m;
    m.stamp_ns = ns;
    m.frame = options.wrench_frame_id.empty() ? options.sensor_frame : options.wrench_frame_id;
    const Eigen::Vector3d n_base = w.head<3>(), f_base = w.segment<3>(3);
    m.force = S.rotation.transpose() * f_base;
    m.torque = S.rotation.transpose() * (n_base - S.translation.cross(f_base));
    sink.wrench(ns, m);
  }
}
}  // namespace

void writeSuspendedRecording(const std::string& path, const FloatingModel& model,
                             const SuspendedMotion& motion,
                             const SuspendedRecordingOptions& options) {
  JointStateDb3 bag(path, {"/joint_states", "/imu", "/ft", "/contact"},
                    {"sensor_msgs/msg/JointState", "sensor_msgs/msg/Imu",
                     "geometry_msgs/msg/WrenchStamped", "std_msgs/msg/Bool"});
  SuspendedSink sink;
  sink.joints = [&](std::int64_t ns, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                    const Eigen::VectorXd& tau) {
    bag.add(ns, ns + 1000000, model.limbs().joint_names, q.data(), dq.data(),
            options.torques ? tau.data() : nullptr, 0);
  };
  sink.imu = [&](std::int64_t ns, const ImuSample& m, const Eigen::Matrix3d&) {
    bag.addEncoded(1, ns + 1000000, cdrImu(m));
  };
  sink.wrench = [&](std::int64_t ns, const WrenchSample& m) {
    bag.addEncoded(2, ns + 1000000, cdrWrench(m));
  };
  suspendedSamples(model, motion, options, sink);
  // The switch: no header, so its time is the receive time (stamps from 1e9 ns, as the sensors').
  for (int k = 0; options.contact_switch && k <= std::lround(options.seconds * 100.0); ++k) {
    if (options.switch_on_change && k != 0 && k != 300 && k != 450) continue;
    const std::int64_t ns = 1000000000 + 10000000LL * k;
    const bool holds = k < 300 || (options.switch_on_change && k >= 450);
    bag.addEncoded(3, ns, std::string("\x00\x01\x00\x00", 4) + (holds ? '\x01' : '\x00'));
  }
  bag.close();
}

void writeSuspendedTable(const std::string& path, const FloatingModel& model,
                         const SuspendedMotion& motion, const SuspendedRecordingOptions& options) {
  const int n = model.numJoints();
  const std::string& imu = options.imu_frame;
  const std::string& ft = options.sensor_frame;
  std::string header = "t";
  for (const char* block : {"q", "dq", "tau"})
    for (const std::string& j : model.limbs().joint_names)
      header += std::string(",") + block + ":" + j;
  for (const char* c : {"qw", "qx", "qy", "qz"}) header += std::string(",base:") + c;
  for (const char* c : {"wx", "wy", "wz", "ax", "ay", "az"}) header += ",imu:" + imu + ":" + c;
  for (const char* c : {"nx", "ny", "nz", "fx", "fy", "fz"}) header += ",wrench:" + ft + ":" + c;
  header += ",contact:" + ft;
  // Each row one sensor's sample, the other sensors' fields empty; rows in time order.
  std::multimap<std::int64_t, std::string> rows;
  const auto row = [&](std::int64_t ns, int skip_before, const std::vector<double>& values,
                       int skip_after) {
    std::ostringstream line;
    line.precision(17);
    line << static_cast<double>(ns - 1000000000) * 1e-9 << std::string(skip_before, ',');
    for (double v : values) line << ',' << v;
    line << std::string(skip_after, ',');
    rows.emplace(ns, line.str());
  };
  SuspendedSink sink;
  sink.joints = [&](std::int64_t ns, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                    const Eigen::VectorXd& tau) {
    std::vector<double> v(q.data(), q.data() + n);
    v.insert(v.end(), dq.data(), dq.data() + n);
    v.insert(v.end(), tau.data(), tau.data() + n);
    row(ns, 0, v, 4 + 6 + 6 + 1);
  };
  sink.imu = [&](std::int64_t ns, const ImuSample& m, const Eigen::Matrix3d& base_rotation) {
    const Eigen::Quaterniond b(base_rotation);
    row(ns, 3 * n,
        {b.w(), b.x(), b.y(), b.z(), m.gyro[0], m.gyro[1], m.gyro[2], m.accel[0], m.accel[1],
         m.accel[2]},
        6 + 1);
  };
  sink.wrench = [&](std::int64_t ns, const WrenchSample& m) {
    row(ns, 3 * n + 10,
        {m.torque[0], m.torque[1], m.torque[2], m.force[0], m.force[1], m.force[2],
         ns < 1000000000 + 3000000000 ? 1.0 : 0.0},
        0);
  };
  suspendedSamples(model, motion, options, sink);
  std::ofstream out(path);
  out << header << "\n";
  for (const auto& [key, line] : rows) out << line << "\n";
}

}  // namespace dynid::test
