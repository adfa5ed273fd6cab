#include "analysis/monitor/calibration.hpp"

#include <algorithm>
#include <atomic>

#include "analysis/logs/rest.hpp"
#include "analysis/monitor/feeds.hpp"
#include "analysis/monitor/regimes.hpp"
#include "analysis/monitor/states.hpp"
#include "analysis/monitor/watch.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"

namespace dynid {

namespace {

const char* const kStoppedCalibrating = "stopped during the calibration: no thresholds";

/// What the calibration's first kRestSamples samples give: the rest velocities, measured on their
/// stamps and velocities as identify measures its data's (analysis/logs/rest.hpp), and the scales
/// of the moving regimes (analysis/monitor/regimes.hpp). The pass stops there.
struct FirstLook {
  Eigen::VectorXd rest_velocity;
  RegimeScales scales;
};

FirstLook calibrationFirstLook(const Model& model, const MonitorRequest& request,
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
  const Eigen::Map<const Eigen::MatrixXd> velocities(dq.data(), n, count);
  const Eigen::Map<const Eigen::VectorXd> stamps(time.data(), count);
  const std::vector<double> rest = restThresholds(measureRestVelocities(velocities, stamps));
  return {Eigen::Map<const Eigen::VectorXd>(rest.data(), n),
          measureRegimeScales(velocities, stamps)};
}

/// A clean run's statistics per arm state: the residual while moving (over all moving samples, and
/// per joint and moving regime), its change at rest.
struct StateStatistics {
  ResidualStatistics moving, rest;
  std::vector<ResidualStatistics> by_regime;  // joint-major, kMovingRegimes per joint, one each
  Eigen::MatrixXd regime_seconds;             // joints x kMovingRegimes
  double rest_seconds = 0.0;
  Pass pass;
};

/// Joint j's moving residual x_j in its regime; `previous` the joint's last moving sample's
/// residual and regime (a rate needs both samples in the regime).
void addToRegime(StateStatistics& out, Eigen::Index j, int regime, double x, double dt,
                 bool follows, Eigen::VectorXd& one, Eigen::VectorXd& previous_one) {
  ResidualStatistics& s = out.by_regime[static_cast<std::size_t>(j * kMovingRegimes + regime)];
  one[0] = x;
  s.add(one, follows ? &previous_one : nullptr, dt);
  if (follows) out.regime_seconds(j, regime) += dt;
  previous_one[0] = x;
}

StateStatistics calibrationStatistics(const Model& model, const MonitorRequest& request,
                                      const Eigen::VectorXd& gain, const FirstLook& first,
                                      std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  StateStatistics out;
  out.moving.reset(n);
  out.rest.reset(n);
  out.by_regime.resize(static_cast<std::size_t>(n * kMovingRegimes));
  for (ResidualStatistics& s : out.by_regime) s.reset(1);
  out.regime_seconds = Eigen::MatrixXd::Zero(n, kMovingRegimes);
  StateResidual states;
  states.reset(first.rest_velocity);
  MovingRegimes regimes;
  regimes.reset(first.scales.speed, first.scales.acceleration);
  Eigen::VectorXd previous, one = Eigen::VectorXd::Zero(1);
  std::vector<Eigen::VectorXd> previous_one(static_cast<std::size_t>(n), Eigen::VectorXd::Zero(1));
  Eigen::VectorXi previous_regime = Eigen::VectorXi::Constant(n, -1);
  ArmState previous_state = ArmState::kMoving;
  const bool direct = request.residual == MonitorResidual::kDirect;
  out.pass = passOverLog(
      model, request.calibration_file, request, gain,
      [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
          const Eigen::VectorXd& dq) {
        if (direct && !d) throw InputError(request.calibration_file + ": " + kDirectNeedsDdq);
        const ArmState raw = states.update(t, dt, direct ? *d : r, dq, false);
        const Eigen::VectorXi& regime = regimes.update(t, dt, dq);
        // Settling, the residual joins the moving statistics, as before the settling rule: the
        // statistics at rest are those of a settled arm.
        const ArmState state = states.settling() ? ArmState::kMoving : raw;
        const Eigen::VectorXd& x = states.settling() ? (direct ? *d : r) : states.statistic();
        const bool follows = dt > 0.0 && state == previous_state;
        if (state == ArmState::kRest) {
          out.rest.add(x, follows ? &previous : nullptr, dt);
          out.rest_seconds += dt;  // as Watch counts it
        } else {
          out.moving.add(x, follows ? &previous : nullptr, dt);
          for (Eigen::Index j = 0; j < n; ++j)
            addToRegime(out, j, regime[j], x[j], dt, follows && regime[j] == previous_regime[j],
                        one, previous_one[static_cast<std::size_t>(j)]);
        }
        if (state == ArmState::kRest)
          previous_regime.setConstant(-1);
        else
          previous_regime = regime;
        previous = x;
        previous_state = state;
      },
      warnings);
  return out;
}

/// Moving, the thresholds that judged an event's largest values raised above them: a regime's
/// own, or the joint's moving threshold where the regime has none.
void raiseMoving(const Watch& watch, MonitorThresholds& t) {
  constexpr double kAbove = 1.0 + 1e-9;  // that sample no longer crosses
  if (t.values_by_regime.size() == 0) {
    t.values = t.values.cwiseMax(watch.eventPeakMoving() * kAbove);
    return;
  }
  const Eigen::MatrixXd& peak = watch.eventPeakByRegime();
  for (Eigen::Index j = 0; j < t.values.size(); ++j)
    for (int c = 0; c < kMovingRegimes; ++c) {
      double& u = t.values_by_regime(j, c) > 0.0 ? t.values_by_regime(j, c) : t.values[j];
      u = std::max(u, peak(j, c) * kAbove);
    }
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
    raiseMoving(watch, thresholds);
    if (thresholds.values_at_rest.size() > 0)
      thresholds.values_at_rest =
          thresholds.values_at_rest.cwiseMax(watch.eventPeakAtRest() * (1.0 + 1e-9));
  }
}

/// Moving, each joint's threshold per regime where the calibration spent kMinRegimeSeconds in it,
/// at the same rate per second of the regime's own time (so the joint's rate stays `rate`).
void regimeThresholdsOf(const StateStatistics& stats, const RegimeScales& scales, double rate,
                        MonitorThresholds& out) {
  const Eigen::Index n = out.values.size();
  out.speed_scale = scales.speed;
  out.acceleration_scale = scales.acceleration;
  out.regime_seconds = stats.regime_seconds;
  out.values_by_regime = Eigen::MatrixXd::Zero(n, kMovingRegimes);
  for (Eigen::Index j = 0; j < n; ++j)
    for (int c = 0; c < kMovingRegimes; ++c)
      if (stats.regime_seconds(j, c) >= kMinRegimeSeconds)
        out.values_by_regime(j, c) = riceThresholds(
            stats.by_regime[static_cast<std::size_t>(j * kMovingRegimes + c)], rate)[0];
}

}  // namespace

MonitorThresholds calibrate(const Model& model, const MonitorRequest& request,
                            const Eigen::VectorXd& gain, std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  const FirstLook first = calibrationFirstLook(model, request, gain);
  // The observer's friction at rest from here on: the calibration's rest velocities.
  const Model rested = withRestVelocities(model, first.rest_velocity);
  const StateStatistics stats = calibrationStatistics(rested, request, gain, first, warnings);
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
  out.rest_velocity = first.rest_velocity;
  regimeThresholdsOf(stats, first.scales, rate, out);
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
  raiseToTheCleanRun(rested, request, gain, out);
  return out;
}

}  // namespace dynid
