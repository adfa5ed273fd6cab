// The moving arm's regimes, per joint: how fast the joint moves (slow: near a reversal, or held
// while other joints move; cruising; fast) and whether it accelerates. Moving, each joint is judged
// by its regime's threshold. The model's error differs between them (friction's sign near a
// reversal, the viscous friction's error with speed, the inertia's with acceleration), and one
// threshold for all of them is set by the worst: a push where the model is good must then exceed
// the error where it is bad. Constant memory, one sample at a time.
#pragma once

#include <array>

#include <Eigen/Core>

#include "analysis/records/monitor_record.hpp"

namespace dynid {

// The constants below were chosen on build/bench/bench_monitor --benchmark_filter=MonitorRegimes
// (docs/MONITOR.md, "The moving regimes").

/// A joint is slow below this share of its speed scale (the 95th percentile of its smoothed |dq| on
/// the calibration): on a sinusoid of amplitude A, below 0.1 A, the 6 % of the period around each
/// reversal where the friction's sign is unsure and the static friction takes over.
inline constexpr double kSlowSpeedShare = 0.1;
/// It is fast above this share: the viscous friction's error grows with the speed.
inline constexpr double kFastSpeedShare = 0.7;
/// It accelerates above this share of its acceleration scale (the 95th percentile of its smoothed
/// |ddq|): the inertia's error grows with the acceleration.
inline constexpr double kAcceleratingShare = 0.5;
/// A regime is kept this long after the joint left it [s], where the residual can still carry its
/// error: the observer's lag (1/K = 10 ms at the default gain, e^-3 after 30 ms) and the 20 ms
/// smoothing of the velocity the regime is read from.
inline constexpr double kRegimeMemorySeconds = 0.05;
/// A regime needs this much of the calibration's moving time for a threshold of its own [s]: ten
/// 1 s blocks, so that the Gumbel law of its maxima, not only Rice's Gaussian formula, sets it.
/// With 2 s, the real Panda's 16 s calibration gave regimes of 2 to 8 s whose thresholds were
/// 0.08 to 0.73 times the single one, and a false alarm on its held-out part. With less, the
/// joint's moving threshold applies in the regime.
inline constexpr double kMinRegimeSeconds = 10.0;

/// The regime's index (0 to kMovingRegimes - 1, the order of kMovingRegimeNames).
inline constexpr int regimeIndex(int speed_class, bool accelerating) {
  return 2 * speed_class + (accelerating ? 1 : 0);
}

/// Each joint's regime, per sample, from its velocity.
class MovingRegimes {
 public:
  /// speed_scale, acceleration_scale: per joint (> 0; a joint with a zero scale stays cruising and
  /// steady, whose threshold is then the moving one). Empty: no regimes.
  void reset(const Eigen::VectorXd& speed_scale, const Eigen::VectorXd& acceleration_scale);
  /// Forgets the past (a gap in the log).
  void restart() { fresh_ = true; }
  /// One sample: time t, step dt (0 after a restart) and the measured velocity dq. Returns each
  /// joint's regime.
  const Eigen::VectorXi& update(double t, double dt, const Eigen::VectorXd& dq);
  const Eigen::VectorXi& regimes() const { return regime_; }
  bool enabled() const { return speed_scale_.size() > 0; }
  /// The smoothed velocity and its smoothed derivative the regimes are read from.
  const Eigen::VectorXd& velocity() const { return velocity_; }
  const Eigen::VectorXd& acceleration() const { return acceleration_; }

 private:
  Eigen::VectorXd speed_scale_, acceleration_scale_, velocity_, acceleration_;
  Eigen::VectorXd last_slow_, last_fast_, last_accelerating_;  // when each joint last was [s]
  Eigen::VectorXi regime_;
  bool fresh_ = true;
};

/// A log's smoothed speed and acceleration, per joint: the 95th percentiles that scale the regimes
/// (dq: joints x samples; time: samples, increasing).
struct RegimeScales {
  Eigen::VectorXd speed, acceleration;
};
RegimeScales measureRegimeScales(const Eigen::MatrixXd& dq, const Eigen::VectorXd& time);

/// Each joint's threshold for its regime: thresholds.values_by_regime where it has one, else the
/// moving threshold (out is resized to the joints).
void regimeThresholds(const MonitorThresholds& thresholds, const Eigen::VectorXi& regimes,
                      Eigen::VectorXd& out);

}  // namespace dynid
