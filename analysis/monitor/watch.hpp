// The monitor's judge, sample by sample: the arm state (analysis/monitor/states.hpp) picks the
// statistic and the thresholds (moving: the residual against each joint's threshold for its moving
// regime, analysis/monitor/regimes.hpp; at rest: its change against the thresholds at rest), and
// the event detector turns crossings into events. The monitored pass and the calibration's
// clean-run check both use it, so they judge alike.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "analysis/monitor/events.hpp"
#include "analysis/monitor/regimes.hpp"
#include "analysis/monitor/states.hpp"
#include "analysis/records/monitor_record.hpp"

namespace dynid {

class Watch {
 public:
  /// Keeps references to `thresholds` and `events`. The rest state is used where the thresholds
  /// have thresholds at rest.
  Watch(const MonitorThresholds& thresholds, double hold, MonitorEventSink* sink,
        std::vector<MonitorEvent>& events);
  /// One sample (dt = 0 after a restart): returns whether the arm is at rest.
  bool sample(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq);
  /// The data ended (or were stopped) during an event.
  void close() { detector_.close(); }
  double restSeconds() const { return rest_seconds_; }  // settled at rest
  /// Per joint, the largest |statistic| while an event was open (at rest, moving).
  const Eigen::VectorXd& eventPeakAtRest() const { return peak_rest_; }
  const Eigen::VectorXd& eventPeakMoving() const { return peak_moving_; }
  /// Moving, per joint and regime (joints x kMovingRegimes), where the thresholds have regimes.
  const Eigen::MatrixXd& eventPeakByRegime() const { return peak_by_regime_; }

 private:
  const MonitorThresholds& thresholds_;
  std::vector<MonitorEvent>& events_;
  EventDetector detector_;
  StateResidual states_;
  MovingRegimes regimes_;
  Eigen::VectorXd peak_rest_, peak_moving_, limits_;
  Eigen::MatrixXd peak_by_regime_;
  double rest_seconds_ = 0.0;
  bool building_ = false;
};

}  // namespace dynid
