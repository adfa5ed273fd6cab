// The monitor's thresholds document (kind dynid.monitor_thresholds): the thresholds a calibration
// set, and their reader. Its writer is reports/monitor_report (thresholdsJson).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// Default false alarms per hour (the whole arm) the calibrated thresholds are set for.
inline constexpr double kDefaultFalseAlarmsPerHour = 0.1;

/// The moving arm's regimes per joint (analysis/monitor/regimes.hpp): its speed class (slow,
/// cruising, fast) by whether it accelerates, in this order.
inline constexpr int kMovingRegimes = 6;
inline constexpr std::array<const char*, kMovingRegimes> kMovingRegimeNames = {
    "slow", "slow_accelerating", "cruising", "cruising_accelerating", "fast", "fast_accelerating"};

/// Which residual raises events.
enum class MonitorResidual { kObserver, kDirect };

/// Thresholds per joint, and where they came from.
struct MonitorThresholds {
  int schema_version = 0;                // read back: the version it was written in
  std::string robot;                     // the model's name
  std::vector<std::string> joint_names;  // they must match the monitored robot's
  MonitorResidual residual = MonitorResidual::kObserver;
  Eigen::VectorXd gain;    // the observer gain they were calibrated with [1/s]
  Eigen::VectorXd values;  // [N m]
  std::string source;      // "calibration FILE" or "thresholds FILE"
  double false_alarms_per_hour = kDefaultFalseAlarmsPerHour;
  Eigen::VectorXd calibration_rms, calibration_max;  // of the residual on the calibration run
  double calibration_seconds = 0.0;
  /// The arm states (analysis/monitor/states.hpp). A joint is at rest within its rest velocity
  /// [rad/s or m/s], measured on the calibration log (empty: no rest state, version 1 files).
  Eigen::VectorXd rest_velocity;
  /// At rest, the thresholds of the residual's change from its level at rest [N m] (empty: the
  /// calibration held no pose long enough, and the moving thresholds apply at rest too).
  Eigen::VectorXd values_at_rest, calibration_rest_rms;
  double rest_seconds = 0.0;  // the calibration's time settled at rest [s]
  /// Moving, thresholds per regime (version 3): the joint's speed and acceleration against these
  /// scales [rad/s, rad/s^2 or m/s, m/s^2], measured on the calibration (empty: one moving
  /// threshold, version 1 and 2 files).
  Eigen::VectorXd speed_scale, acceleration_scale;
  /// joints x kMovingRegimes [N m]; 0 where the calibration spent less than kMinRegimeSeconds in
  /// the regime (`values` applies there).
  Eigen::MatrixXd values_by_regime;
  Eigen::MatrixXd regime_seconds;  // joints x kMovingRegimes: the calibration's time in each [s]
};

/// Reads a thresholds document (kind dynid.monitor_thresholds). Throws ParseError naming the field.
MonitorThresholds readMonitorThresholds(const std::string& file);

}  // namespace dynid
