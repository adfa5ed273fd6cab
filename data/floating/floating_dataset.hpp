// Floating-base datasets (docs/FLOATING.md, "Datasets"): a floating robot's samples as a CSV table
// whose columns are named, in any order, one sample per row, SI units:
//   t                                   time [s], increasing
//   base:qw, base:qx, base:qy, base:qz  the base orientation, a unit quaternion rotating base-frame
//                                       vectors into the world (within 1e-3 of unit: normalised)
//   base:wx .. base:wz, base:vx .. vz   the base twist (omega, v) in the base frame
//   base:dwx .. base:dwz, base:dvx ..   its derivative (floating_model.hpp's convention)
//   q:J, dq:J, ddq:J                    every joint J of the model, by name
//   tau:J                               the joint torques, for every joint or none
//   wrench:F:fx, :fy, :fz               a contact force the environment exerts on frame F (a
//                                       link of the model), through F's origin, in F's axes
//   wrench:F:nx, :ny, :nz               with those, a moment about F's origin: a wrench
//   contact:F                           1 when the contact at F holds, 0 when not (a flag)
//   imu:F:wx, :wy, :wz, :ax, :ay, :az   instead of the base twist and its derivative: an IMU on
//                                       the base body at frame F, its gyro [rad/s] and its
//                                       accelerometer's specific force [m/s^2] in F's axes
// A frame may carry a wrench, a flag or both.
//
// From an IMU the base's motion is what the dynamics need, not the twist a state estimator would
// give: omega from the gyro, its derivative by differences over t (three-point, uneven steps;
// one-sided at the ends), and the base origin's acceleration from the specific force (plus
// gravity, minus the IMU's lever arm); the base's linear velocity is set to zero and its
// derivative to that acceleration. The forces do not depend on the base's linear velocity given
// its origin's acceleration (a moving frame's inertial forces are its accelerations' and its
// angular velocity's), so the rows are the same.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/floating/floating_model.hpp"
#include "data/io.hpp"

namespace dynid {

struct FloatingDataset {
  /// A contact force measured at a named frame: 3 rows (fx, fy, fz) or 6 (nx, ny, nz, fx, fy, fz:
  /// dynid's angular-first order), one column per sample, in the frame's axes.
  struct Wrench {
    std::string frame;
    Eigen::MatrixXd values;
  };
  /// Whether the contact at a named frame holds, per sample (0 or 1).
  struct Flag {
    std::string frame;
    std::vector<char> holding;
  };

  std::string file;                 // where it was read from (empty: in memory)
  std::vector<std::string> joints;  // the model's joint names, the rows of q, dq, ddq, tau
  Eigen::VectorXd time;             // N
  Eigen::Matrix4Xd orientation;     // (w, x, y, z) per sample, unit
  Eigen::Matrix<double, 6, Eigen::Dynamic> twist, acceleration;  // base frame, (omega, v)
  Eigen::MatrixXd q, dq, ddq;                                    // n x N
  Eigen::MatrixXd tau;  // n x N, or 0 x N: no torque measured
  std::vector<Wrench> wrenches;
  std::vector<Flag> flags;
  std::vector<int> lines;  // the file line of each sample (empty: in memory)
  /// The IMU frame the base's motion came from (empty: base: columns).
  std::string imu_frame;

  int numSamples() const { return static_cast<int>(time.size()); }
  bool hasTorques() const { return tau.rows() > 0; }
  /// The wrench or flag of a frame, or nullptr.
  const Wrench* findWrench(const std::string& frame) const;
  const Flag* findFlag(const std::string& frame) const;
  /// The file line of sample k for messages (k + 2 when the dataset was not read from a file).
  int line(int k) const { return lines.empty() ? k + 2 : lines[static_cast<std::size_t>(k)]; }
};

/// The header of a dataset of that shape (its columns in the order writeFloatingDataset writes).
std::string floatingDatasetHeader(const FloatingDataset& dataset);

/// Writes the dataset atomically (data/io.hpp), numbers in shortest round-trip form. Throws
/// InputError when its sizes disagree, Error when the file cannot be written.
void writeFloatingDataset(const std::string& path, const FloatingDataset& dataset);
/// The same rows into a writer the caller commits (an output set's file).
void writeFloatingDataset(AtomicWriter& out, const FloatingDataset& dataset);

/// The base's twist and its derivative at one sample from an IMU on the base body at placement
/// `imu` (in the base frame), by the rule above: `rotation` the base's orientation (base to world),
/// the gyro, its time derivative and the specific force, all three in the IMU's axes.
void imuBaseMotion(const FloatingModel& model, const Pose<double>& imu,
                   const Eigen::Matrix3d& rotation, const Eigen::Vector3d& gyro,
                   const Eigen::Vector3d& dgyro, const Eigen::Vector3d& specific_force,
                   Eigen::Ref<Vector6<double>> twist, Eigen::Ref<Vector6<double>> acceleration);

/// Reads a dataset of `model`. Throws ParseError naming the file, the line and the column of what
/// is wrong: an unknown column, a joint the model lacks or a joint it has that the file lacks, a
/// wrench or flag in a frame the model does not have (the frames named), a wrench without all of
/// fx, fy, fz or with some moment components only, torques for some joints only, a field that is
/// not a finite number, a flag that is not 0 or 1, a quaternion that is not unit (its norm),
/// time not increasing, a file with no sample, an IMU not on the base body, two IMUs, an IMU and
/// base: twist columns both, an IMU with one sample (no derivative); Error when it cannot be read.
FloatingDataset readFloatingDataset(const std::string& path, const FloatingModel& model);

}  // namespace dynid
