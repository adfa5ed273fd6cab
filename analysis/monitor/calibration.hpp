// The monitor's calibration: thresholds per arm state from a clean log. The log's rest velocities
// (analysis/logs/rest.hpp), the residual's statistics moving and its change at rest, the
// thresholds at the requested false-alarm rate, then raised until the clean log itself, judged as
// a monitored log is (analysis/monitor/watch.hpp), raises no alarm.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/monitor/monitor.hpp"
#include "core/model.hpp"

namespace dynid {

/// Thresholds from request.calibration_file with the observer of `gain`. Throws InputError for a
/// calibration stopped early, one that never moves, a zero residual, or what the feeds throw.
MonitorThresholds calibrate(const Model& model, const MonitorRequest& request,
                            const Eigen::VectorXd& gain, std::vector<std::string>& warnings);

}  // namespace dynid
