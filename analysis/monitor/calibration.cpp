#include "analysis/monitor/calibration.hpp"

#include <atomic>

#include "analysis/logs/rest.hpp"
#include "analysis/monitor/feeds.hpp"
#include "analysis/monitor/states.hpp"
#include "analysis/monitor/watch.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"

namespace dynid {

namespace {

const char* const kStoppedCalibrating = "stopped during the calibration: no thresholds";

/// The calibration log's rest velocities: measured on its first kRestSamples samples' stamps and
/// velocities (analysis/logs/rest.hpp), as identify measures its data's. The pass stops there.
Eigen::VectorXd calibrationRestVelocities(const Model& model, const MonitorRequest& request,
                                          const Eigen::VectorXd& gain) {
  const int n = model.numJoints();
  std::vector<double> time, dq;  // dq: joint-major per sample
  std::atomic<bool> enough{false};
  MonitorRequest first = request;
  first.control.stop = &enough;      // the user's Ctrl-C is forwarded below
  std::vector<std::string> ignored;  // the statistics' pass reports the same warnings
  passOverLog(
      model, request.calibration_file, first, gain,
      [&](double t, double, const Eigen::VectorXd&, const Eigen::VectorXd*,
          const Eigen::VectorXd& v) {
        time.push_back(t);
        dq.insert(dq.end(), v.data(), v.data() + v.size());
        if (time.size() >= static_cast<std::size_t>(kRestSamples) || request.control.interrupted())
          enough = true;
      },
      ignored);
  if (request.control.interrupted()) throw InputError(kStoppedCalibrating);
  const Eigen::Index count = static_cast<Eigen::Index>(time.size());
  const std::vector<double> rest =
      restThresholds(measureRestVelocities(Eigen::Map<const Eigen::MatrixXd>(dq.data(), n, count),
                                           Eigen::Map<const Eigen::VectorXd>(time.data(), count)));
  return Eigen::Map<const Eigen::VectorXd>(rest.data(), n);
}

/// A clean run's statistics per arm state: the residual while moving, its change at rest.
struct StateStatistics {
  ResidualStatistics moving, rest;
  double rest_seconds = 0.0;
  Pass pass;
};

StateStatistics calibrationStatistics(const Model& model, const MonitorRequest& request,
                                      const Eigen::VectorXd& gain,
                                      const Eigen::VectorXd& rest_velocity,
                                      std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  StateStatistics out;
  out.moving.reset(n);
  out.rest.reset(n);
  StateResidual states;
  states.reset(rest_velocity);
  Eigen::VectorXd previous;
  ArmState previous_state = ArmState::kMoving;
  const bool direct = request.residual == MonitorResidual::kDirect;
  out.pass = passOverLog(
      model, request.calibration_file, request, gain,
      [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
          const Eigen::VectorXd& dq) {
        if (direct && !d) throw InputError(request.calibration_file + ": " + kDirectNeedsDdq);
        const ArmState state = states.update(t, dt, direct ? *d : r, dq, false);
        const Eigen::VectorXd& x = states.statistic();
        const bool follows = dt > 0.0 && state == previous_state;
        if (state == ArmState::kRest) {
          out.rest.add(x, follows ? &previous : nullptr, dt);
          out.rest_seconds += dt;  // as Watch counts it
        } else {
          out.moving.add(x, follows ? &previous : nullptr, dt);
        }
        previous = x;
        previous_state = state;
      },
      warnings);
  return out;
}

/// The clean run raises no alarm: the calibration log judged as a monitored log is. At rest the
/// level stands still while a change builds, which the statistics above do not see; a joint whose
/// statistic then crosses its threshold has it raised to the largest value of that event, and the
/// log is judged again (a higher threshold holds the level less; at most kMaxRaises passes).
void raiseToTheCleanRun(const Model& model, const MonitorRequest& request,
                        const Eigen::VectorXd& gain, MonitorThresholds& thresholds) {
  constexpr int kMaxRaises = 5;
  const bool direct = request.residual == MonitorResidual::kDirect;
  for (int pass = 0; pass < kMaxRaises; ++pass) {
    std::vector<MonitorEvent> events;
    std::vector<std::string> ignored;  // the statistics' pass reported them
    Watch watch(thresholds, request.hold, nullptr, events);
    const Pass judged = passOverLog(
        model, request.calibration_file, request, gain,
        [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
            const Eigen::VectorXd& dq) { watch.sample(t, dt, direct ? *d : r, dq); },
        ignored);
    if (judged.interrupted) throw InputError(kStoppedCalibrating);  // a part judged is no check
    watch.close();
    if (events.empty()) return;
    // 1e-9 above the largest value: that sample no longer crosses.
    thresholds.values = thresholds.values.cwiseMax(watch.eventPeakMoving() * (1.0 + 1e-9));
    if (thresholds.values_at_rest.size() > 0)
      thresholds.values_at_rest =
          thresholds.values_at_rest.cwiseMax(watch.eventPeakAtRest() * (1.0 + 1e-9));
  }
}

}  // namespace

MonitorThresholds calibrate(const Model& model, const MonitorRequest& request,
                            const Eigen::VectorXd& gain, std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  const Eigen::VectorXd rest_velocity = calibrationRestVelocities(model, request, gain);
  const StateStatistics stats =
      calibrationStatistics(model, request, gain, rest_velocity, warnings);
  if (stats.pass.interrupted) throw InputError(kStoppedCalibrating);
  if (stats.moving.samples == 0)
    throw InputError(request.calibration_file +
                     ": the arm holds its pose throughout the calibration: thresholds for motion "
                     "cannot be set from it (calibrate on a log that moves, with stops)");
  MonitorThresholds out;
  out.robot = model.name;
  out.joint_names = model.joint_names;
  out.residual = request.residual;
  out.gain = gain;
  out.false_alarms_per_hour = request.false_alarms_per_hour;
  const double rate = request.false_alarms_per_hour / 3600.0 / n;
  out.values = riceThresholds(stats.moving, rate);
  out.source = "calibration " + request.calibration_file;
  out.calibration_rms = stats.moving.rms();
  out.calibration_max = stats.moving.max_abs;
  out.calibration_seconds = stats.pass.last - stats.pass.first;
  out.rest_velocity = rest_velocity;
  out.rest_seconds = stats.rest_seconds;
  if (stats.rest_seconds >= kMinRestSeconds) {
    out.values_at_rest = riceThresholds(stats.rest, rate);
    out.calibration_rest_rms = stats.rest.rms();
  }
  if ((out.values.array() <= 0.0).any() ||
      (out.values_at_rest.size() > 0 && (out.values_at_rest.array() <= 0.0).any()))
    throw InputError(request.calibration_file +
                     ": the calibration residual is zero on some joint (a log without motion or "
                     "torque?): no threshold can be set from it");
  raiseToTheCleanRun(model, request, gain, out);
  return out;
}

}  // namespace dynid
