// dynid monitor: an identified model watching a robot's log (or its live samples) for external
// torques. A generalized-momentum observer (needs q, dq and tau only), the direct residual
// tau - tau_hat where the log has ddq, per-joint thresholds per arm state (moving, at rest) from a
// clean calibration log at a chosen false-alarm rate (calibration.hpp) or from a saved thresholds
// file, and the events where a residual (at rest: its change from the level at rest) crosses them
// (watch.hpp). Constant memory: a log of any length, or a stream that never ends.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/monitor/events.hpp"
#include "analysis/monitor/observer.hpp"
#include "analysis/records/model_source.hpp"
#include "analysis/records/monitor_record.hpp"
#include "core/model.hpp"
#include "core/run_control.hpp"

namespace dynid {

/// A step between samples longer than this restarts the observer (a gap in the log) [s].
inline constexpr double kDefaultMaxGap = 0.1;

struct MonitorRequest {
  std::string arm;         // an estimate.json, an identified URDF, a dynid JSON model or robot
  std::string robot_spec;  // with an estimate.json: the robot (default: the estimate's)
  std::string data_file;   // a dataset CSV, a recording, or "-" for samples streamed on stdin
  std::string calibration_file;  // a clean dataset CSV or recording to set the thresholds from, or
  std::string thresholds_file;   // a saved thresholds.json (exactly one of the two)
  std::string truth_file;        // simulate --disturbance's ground truth (optional)
  MonitorResidual residual = MonitorResidual::kObserver;
  std::optional<Eigen::VectorXd> gain;  // per joint, or one for all [1/s] (default 100)
  double false_alarms_per_hour = kDefaultFalseAlarmsPerHour;
  double hold = kDefaultEventHold;
  double max_gap = kDefaultMaxGap;
  int threads = 0;
  /// Recordings (ROS bags: .mcap, .db3, .bag or a bag directory; analysis/logs/bag_log.hpp) as
  /// data or calibration: sensor_msgs/JointState with position, velocity and effort, joints matched
  /// by name to the model's. Their JointState topic (empty: the only one), the stamp (header, or
  /// receive time) and the topic whose efforts are the torques when the positions' carry none.
  std::string topic, effort_topic;
  std::string joint_prefix;  // LogSource::joint_prefix
  /// Recordings: the messages' names of the arm's joints, in its joint order (empty: the arm's
  /// own names; else one per joint).
  std::vector<std::string> joint_names = {};
  bool receive_time = false;
  /// Raw efforts that are motor currents (a current-sensing arm's recording or stdin samples):
  /// tau_j = current_j * torque_constants_j * gear_ratios_j [N m/A; gear ratios empty: 1], as
  /// dynid prepare --current. A dataset CSV's tau is taken as it is (prepare converted it); at
  /// least one of the logs must be a recording or stdin. One entry per joint each.
  Eigen::VectorXd torque_constants, gear_ratios;
  MonitorEventSink* sink = nullptr;  // events as they happen (may be null)
  /// Lines streamed from stdin when data_file is "-" (the CLI's reader; tests pass their own).
  std::function<bool(std::string& line)> next_line;
  RunControl control;  // Ctrl-C: stop after the current sample, with the events so far
  /// Throws InputError naming the first option out of range, or for both or neither of the
  /// threshold sources.
  void check() const;
};

struct MonitorOutcome {
  Model model;
  std::string robot_spec;
  ModelSource source;  // where the arm's robot came from (monitor.json, thresholds.json embed it)
  MonitorThresholds thresholds;
  std::vector<MonitorEvent> events;
  long long samples = 0;
  double seconds = 0.0;       // from the first sample to the last
  double rest_seconds = 0.0;  // of which settled at rest (where the thresholds have a rest state)
  int restarts = 0;           // gaps longer than max_gap
  bool has_direct = false;    // the data carried ddq (files do; stdin may not)
  Eigen::VectorXd observer_rms, observer_max, direct_rms, direct_max;  // over the data
  ResidualEnvelope observer_envelope, direct_envelope;
  std::optional<TruthScore> truth;
  bool interrupted = false;  // stopped (Ctrl-C) after the thresholds; samples may be 0
  std::vector<std::string> warnings;
};

/// Loads the arm, sets the thresholds (a calibration pass or the file), then runs the observer (and
/// the direct residual where ddq is given) over the data, reporting events to request.sink as they
/// start and end. A recording is read whole, its samples taken at their own stamps in time order
/// (repeated stamps dropped, counted in a warning), unfiltered; it has no ddq (observer only).
/// Throws InputError for a bad request, data of another joint count, thresholds of other joints, a
/// recording without the robot's joints or without velocities (prepare it first), or with a
/// non-finite value (naming the file, the sample and the field); ParseError naming the file (or
/// "<stdin>"), line and column for a malformed sample, a non-finite value, time that does not
/// increase or a stream that ends mid-line. Stopped (request.control) during the calibration it
/// throws InputError (no thresholds); after it, it returns the events so far, interrupted.
MonitorOutcome monitorRun(const MonitorRequest& request);

/// `model` with the rest velocities the monitor measured (thresholds.rest_velocity: the
/// calibration's, on the monitored sensor): its friction at rest is then the static friction's
/// point value, not Fc sign(noise) (core/drive_terms.hpp), whatever the arm carried (an estimate's
/// are its identification log's, a model or URDF carries none). `rest_velocity` of another size
/// than the joints (thresholds saved without it) leaves the model as it is.
Model withRestVelocities(const Model& model, const Eigen::VectorXd& rest_velocity);

/// What a calibration run can confirm about its false-alarm rate. With no alarm in T seconds of
/// clean calibration, the rate is below 3 / T at 95 % (the rule of three: P(no event) = exp(-3) =
/// 5 %); a lower rate rests on the residual's Gaussian tail (Rice's formula), not on the data.
struct CalibrationConfidence {
  double seconds = 0.0;             // T, the calibration's length
  double confirmed_per_hour = 0.0;  // 3 / T, per hour: the lowest rate T seconds can confirm
  double needed_seconds = 0.0;      // 3 / rate: the calibration the chosen rate would need
  bool extrapolated = false;        // the chosen rate is below what T confirms
};
/// From thresholds calibrated on a run (calibration_seconds > 0); nothing for read-back ones.
std::optional<CalibrationConfidence> calibrationConfidence(const MonitorThresholds& thresholds);

}  // namespace dynid
