// Floating robots' recordings for tests: sensor_msgs/Imu and geometry_msgs/WrenchStamped encoded
// from their message definitions (ROS 2 CDR, little endian, XCDR1 alignment; ROS 1's plain
// serialization), and a rosbag2 recording of a robot hung from a force-torque sensor on a moving
// support, its motion analytic so that every prepared signal has an exact value to meet.
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "core/floating/floating_data.hpp"
#include "core/floating/floating_model.hpp"

namespace dynid::test {

struct ImuSample {
  std::int64_t stamp_ns = 0;
  std::string frame;
  Eigen::Vector4d xyzw = Eigen::Vector4d(0, 0, 0, 1);
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), accel = Eigen::Vector3d::Zero();
  double orientation_covariance0 = 0.0;  // -1: no orientation
};
struct WrenchSample {
  std::int64_t stamp_ns = 0;
  std::string frame;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
};

std::string cdrImu(const ImuSample& m);
std::string ros1Imu(const ImuSample& m);
std::string cdrWrench(const WrenchSample& m);
std::string ros1Wrench(const WrenchSample& m);

/// A robot hung from a force-torque sensor on a support that turns it about a fixed axis and
/// moves it (or holds it still: `support_moves` false, the "suspended" motion class), the joints
/// swinging: every quantity a closed form of time (seeded amplitudes, frequencies 0.2-0.6 Hz,
/// phases).
class SuspendedMotion {
 public:
  SuspendedMotion(const FloatingModel& model, std::uint64_t seed, bool support_moves = true);
  /// The base's rotation (base to world), twist and its derivative (floating_model.hpp).
  BaseMotion base(double t) const;
  /// The base origin's classical acceleration in base axes (dv + omega x v).
  Eigen::Vector3d originAcceleration(double t) const;
  Eigen::VectorXd q(double t) const, dq(double t) const, ddq(double t) const;

 private:
  Eigen::Matrix3d R0_;
  Eigen::Vector3d axis_, p_amplitude_, p_frequency_, p_phase_;
  double angle_amplitude_, angle_frequency_, angle_phase_;
  Eigen::VectorXd q0_, amplitude_, frequency_, phase_;
};

struct SuspendedRecordingOptions {
  double seconds = 6.0;
  double joint_rate = 500.0, imu_rate = 400.0, wrench_rate = 1000.0;  // [Hz]
  double jitter = 0.2;  // each stamp but the first moved by up to this fraction of its step
  std::string imu_frame = "imu_link", sensor_frame = "face_rear";
  bool torques = true;      // efforts in the joint messages
  bool orientation = true;  // the IMU reports its orientation
  std::uint64_t seed = 1;
  double joint_start = 0.0;     // the joint topic's first stamp [s] (the others start at 0)
  double imu_end = -1.0;        // the IMU's last stamp at most [s]; < 0: seconds
  std::string wrench_frame_id;  // the wrench messages' frame_id; empty: sensor_frame
  bool contact_switch = false;  // a std_msgs/Bool topic /contact at 100 Hz: 1 before 3 s, then 0
  // With contact_switch: the switch publishes only when it changes (1 at 0 s, 0 at 3 s, 1 at 4.5
  // s).
  bool switch_on_change = false;
};

/// Writes a .db3 recording of the motion: /joint_states (every joint), /imu (in imu_frame),
/// /ft (the sensor's wrench on the robot, in sensor_frame's axes about its origin), each at its
/// own rate with jittered stamps, received 1 ms after their stamps; noise-free.
void writeSuspendedRecording(const std::string& path, const FloatingModel& model,
                             const SuspendedMotion& motion,
                             const SuspendedRecordingOptions& options);

/// The same samples as a table (data/floating/floating_log.hpp): each row one sensor's sample,
/// the others' fields empty; the sensor's frame also carries a contact flag, 1 for its samples
/// before 3 s and 0 after.
void writeSuspendedTable(const std::string& path, const FloatingModel& model,
                         const SuspendedMotion& motion, const SuspendedRecordingOptions& options);

}  // namespace dynid::test
