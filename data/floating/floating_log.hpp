// A floating robot's raw log as a table, before preparation (`dynid prepare --floating-base --log
// log.csv`, docs/FLOATING.md "From a recording"): the dataset's column names
// (floating_dataset.hpp) without what a preparation derives:
//   t                                   time [s]
//   q:J                                 every joint J of the model; dq:J and tau:J for every joint
//                                       or none (dq derived from q when absent)
//   base:qw, base:qx, base:qy, base:qz  the base orientation, with
//   imu:F:wx .. imu:F:az                an IMU on the base body at frame F (gyro, specific force)
//   wrench:F:fx, :fy, :fz (:nx, ...)    contact wrenches, as in a dataset
//   contact:F                           contact flags, 0 or 1
// Sensors at different rates share one table: a row leaves a sensor's fields empty where it has
// no sample, all of them (the joints' q, dq and tau together; the IMU's with the orientation; one
// frame's wrench; one flag). Each sensor's samples are then its own signal at its own stamps.
#pragma once

#include <string>
#include <vector>

#include "core/floating/floating_model.hpp"

namespace dynid {

/// One sensor's samples: their times, values (`width` per sample, in order) and file lines.
struct FloatingLogSignal {
  std::string frame;  // the IMU's, a wrench's or a flag's frame (empty: the joints)
  int width = 0;
  std::vector<double> time, values;
  std::vector<int> lines;
  int samples() const { return static_cast<int>(time.size()); }
};

struct FloatingLogTable {
  std::string file;
  /// q (n), then dq (n) when logged, then tau (n) when logged; the model's joint order.
  FloatingLogSignal joints;
  bool has_dq = false, has_tau = false;
  /// The base orientation (w, x, y, z), the gyro and the specific force (10 per sample).
  FloatingLogSignal imu;
  std::vector<FloatingLogSignal> wrenches;  // 6 (nx..nz, fx..fz) or 3 (fx..fz) per sample
  std::vector<FloatingLogSignal> flags;     // 1 (0 or 1) per sample
};

/// Reads a raw floating log of `model`. Throws ParseError naming the file, the line and the
/// column: an unknown column, a joint or frame the model lacks (those it has named), a ddq or
/// base twist column (a preparation derives them), q missing for a joint, dq or tau for some joints
/// only, no IMU (or its orientation), an IMU not on the base body or two IMUs, a wrench without
/// fx, fy and fz or with some moments only, a sensor with some of its fields empty in a row, a
/// field that is not a finite number, a flag that is not 0 or 1, a row without a time, a table
/// with no row; Error when it cannot be read.
FloatingLogTable readFloatingLogTable(const std::string& path, const FloatingModel& model);

}  // namespace dynid
