#include "analysis/monitor/monitor.hpp"

#include <cmath>
#include <limits>

#include "analysis/logs/effort_scale.hpp"
#include "analysis/monitor/calibration.hpp"
#include "analysis/monitor/feeds.hpp"
#include "analysis/monitor/watch.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/upgrade.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "data/bags/bag.hpp"

namespace dynid {

// ---- the request ----

void MonitorRequest::check() const {
  if (calibration_file.empty() == thresholds_file.empty())
    throw InputError(
        "give the thresholds' source: `calibration` CLEAN.csv (a log without contact) or "
        "`thresholds` thresholds.json (a monitor's earlier output), exactly one of them");
  checkOption("monitor", "false-alarms-per-hour", false_alarms_per_hour, "`false_alarms_per_hour`");
  checkOption("monitor", "hold", hold, "`hold`");
  checkOption("monitor", "max-gap", max_gap, "`max_gap`");
  if (gain && (!gain->allFinite() || (gain->array() <= 0.0).any() || (gain->array() > 1e6).any()))
    throw InputError("`gain`: each value must be > 0 and at most 1e6 [1/s]");
  // How a recording is read means nothing for a dataset CSV or stdin: refused, not ignored.
  const bool recording =
      bags::isBag(data_file) || (!calibration_file.empty() && bags::isBag(calibration_file));
  if (!recording && (!topic.empty() || !effort_topic.empty() || !joint_prefix.empty() ||
                     !joint_names.empty() || receive_time))
    throw InputError(
        "`topic`, `stamp` receive, `effort_topic`, `joint_prefix` and `joint_names` apply to "
        "recordings (.mcap, .db3, .bag, bag directories), and neither " +
        data_file + " nor the calibration is one");
}

namespace {

/// Whether `file` holds raw efforts (a recording, or stdin), which --torque-constants scales.
bool rawEfforts(const std::string& file) { return file == "-" || bags::isBag(file); }

/// An estimate identified from motor currents monitoring raw efforts: a warning when no torque
/// constants are given (the efforts are taken as torques, and if they are currents every residual
/// is in another unit), or when they differ from the estimate's.
void currentsWarning(const LoadedArm& arm, const MonitorRequest& request,
                     const Eigen::VectorXd& mine, std::vector<std::string>& warnings) {
  if (arm.torque_constants.empty()) return;
  const auto list = [](const std::vector<double>& v) {
    std::string out;
    for (double x : v) {
      if (!out.empty()) out += ',';
      out += formatNumber(x, 6);
    }
    return out;
  };
  const std::string given =
      "`torque_constants` " + list(arm.torque_constants) +
      (arm.gear_ratios.empty() ? "" : " `gear_ratios` " + list(arm.gear_ratios));
  if (request.torque_constants.size() == 0) {
    warnings.push_back(request.arm +
                       " was identified from motor currents converted to torques (dynid prepare " +
                       given +
                       "); the recording's efforts are taken as joint torques [N m]. If they are "
                       "currents, give the same: " +
                       given);
    return;
  }
  // What matters is the product, current x constant x ratio.
  Eigen::VectorXd theirs = Eigen::Map<const Eigen::VectorXd>(
      arm.torque_constants.data(), static_cast<Eigen::Index>(arm.torque_constants.size()));
  for (std::size_t j = 0; j < arm.gear_ratios.size() && j < arm.torque_constants.size(); ++j)
    theirs[static_cast<Eigen::Index>(j)] *= arm.gear_ratios[j];
  if (mine.size() != theirs.size() ||
      ((mine - theirs).array().abs() > 1e-9 * theirs.array().abs()).any())
    warnings.push_back("the torque constants and gear ratios given differ from those " +
                       request.arm + " was identified with (" + given +
                       "): the residuals then carry the difference");
}

/// The observer gain per joint (one value for all, or the default); InputError for another count.
Eigen::VectorXd checkedGain(const MonitorRequest& request, const Model& model) {
  const int n = model.numJoints();
  Eigen::VectorXd gain = request.gain.value_or(Eigen::VectorXd::Constant(n, kDefaultObserverGain));
  if (gain.size() == 1) gain = Eigen::VectorXd::Constant(n, gain[0]);  // one value for all
  if (gain.size() != n)
    throw InputError("`gain` has " + std::to_string(gain.size()) + " values, the robot '" +
                     model.name + "' has " + std::to_string(n) + " joints");
  return gain;
}

/// The torque constants against the logs (they convert raw efforts: a recording's or stdin's)
/// and against the estimate's own (a warning when they are missing or differ).
void checkEffortScale(const MonitorRequest& request, const LoadedArm& arm,
                      std::vector<std::string>& warnings) {
  const Eigen::VectorXd scale = effortScale(request.torque_constants, request.gear_ratios,
                                            arm.model.numJoints(), "the robot");
  const bool raw_efforts = rawEfforts(request.data_file) || (!request.calibration_file.empty() &&
                                                             rawEfforts(request.calibration_file));
  if (scale.size() > 0 && !raw_efforts)
    throw InputError(
        "`torque_constants` converts the raw efforts of a recording or of samples on stdin; the "
        "dataset CSVs given hold torques already (dynid prepare `current` converted them): drop "
        "`torque_constants`");
  if (raw_efforts) currentsWarning(arm, request, scale, warnings);
}

}  // namespace

namespace {

/// A saved thresholds file, for these joints, this observer gain (when one is given) and this
/// residual; InputError naming what differs.
MonitorThresholds readBackThresholds(const MonitorRequest& request, const Model& model,
                                     const Eigen::VectorXd& gain) {
  MonitorThresholds out = readMonitorThresholds(request.thresholds_file);
  if (out.joint_names != model.joint_names)
    throw InputError(request.thresholds_file + ": thresholds for the joints of '" + out.robot +
                     "' (" + std::to_string(out.joint_names.size()) + " joints), not those of '" +
                     model.name + "': calibrate again on this robot's log");
  if (request.gain && (gain - out.gain).norm() != 0.0)
    throw InputError(request.thresholds_file +
                     ": calibrated with another observer gain; drop `gain` or calibrate again");
  if (out.residual != request.residual)
    throw InputError(request.thresholds_file + ": thresholds of the " +
                     (out.residual == MonitorResidual::kDirect ? "direct" : "observer") +
                     " residual; give the same `residual`");
  return out;
}

}  // namespace

MonitorOutcome monitorRun(const MonitorRequest& request) {
  request.check();
  MonitorOutcome out;
  const LoadedArm arm = loadArm(request.arm, request.robot_spec, std::nullopt, &out.warnings);
  out.model = arm.model;
  out.robot_spec = arm.robot_spec;
  out.source = arm.source;
  const Model& model = out.model;
  const int n = model.numJoints();
  Eigen::VectorXd gain = checkedGain(request, model);
  checkEffortScale(request, arm, out.warnings);
  // The thresholds: calibrated on a clean log, or read back (for these joints, this gain).
  if (!request.calibration_file.empty()) {
    out.thresholds = calibrate(model, request, gain, out.warnings);
  } else {
    out.thresholds = readBackThresholds(request, model, gain);
    if (out.thresholds.schema_version < kMonitorThresholdsDocument.schema_version)
      out.warnings.push_back(olderVersionNote(
          request.thresholds_file, kMonitorThresholdsDocument.kind, out.thresholds.schema_version,
          kMonitorThresholdsDocument.schema_version));
    gain = out.thresholds.gain;
  }
  // The monitored pass, with the friction at rest of the thresholds' rest velocities.
  out.model = withRestVelocities(out.model, out.thresholds.rest_velocity);
  const bool direct_events = request.residual == MonitorResidual::kDirect;
  ResidualStatistics observer_stats, direct_stats;
  observer_stats.reset(n);
  direct_stats.reset(n);
  out.observer_envelope.reset(n);
  out.direct_envelope.reset(n);
  Watch watch(out.thresholds, request.hold, request.sink, out.events);
  const Visit visit = [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
                          const Eigen::VectorXd& dq) {
    observer_stats.add(r, nullptr, 0.0);
    out.observer_envelope.add(t, r);
    if (d) {
      direct_stats.add(*d, nullptr, 0.0);
      out.direct_envelope.add(t, *d);
    }
    watch.sample(t, dt, direct_events ? *d : r, dq);
  };
  Pass pass;
  if (request.data_file == "-") {
    pass = passOverStream(
        model, request, gain,
        [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
            const Eigen::VectorXd& dq) {
          if (direct_events && !d)
            throw InputError("`residual` direct needs ddq: the stream's header has no ddq columns");
          visit(t, dt, r, d, dq);
        });
  } else {
    pass = passOverLog(
        model, request.data_file, request, gain,
        [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
            const Eigen::VectorXd& dq) {
          if (direct_events && !d) throw InputError(request.data_file + ": " + kDirectNeedsDdq);
          visit(t, dt, r, d, dq);
        },
        out.warnings);
  }
  watch.close();
  out.rest_seconds = watch.restSeconds();
  out.samples = pass.samples;
  out.seconds = pass.last - pass.first;
  out.restarts = pass.restarts;
  out.has_direct = pass.has_direct;
  out.interrupted = pass.interrupted;
  out.observer_rms = observer_stats.rms();
  out.observer_max = observer_stats.max_abs;
  if (pass.has_direct) {
    out.direct_rms = direct_stats.rms();
    out.direct_max = direct_stats.max_abs;
  }
  if (out.samples == 0 && !out.interrupted)  // stopped before the first: the thresholds stand
    throw InputError(request.data_file + ": no samples to monitor");
  if (pass.restarts > 0)
    out.warnings.push_back(std::to_string(pass.restarts) + " gap(s) longer than " +
                           std::to_string(request.max_gap) +
                           " s: the observer restarted after each (no external torque assumed "
                           "at a restart)");
  if (!request.truth_file.empty())
    out.truth = scoreEvents(truthEpisodes(request.truth_file, n), out.events);
  return out;
}

Model withRestVelocities(const Model& model, const Eigen::VectorXd& rest_velocity) {
  Model out = model;
  if (rest_velocity.size() == model.numJoints())
    out.rest_velocities.assign(rest_velocity.data(), rest_velocity.data() + rest_velocity.size());
  return out;
}

std::optional<CalibrationConfidence> calibrationConfidence(const MonitorThresholds& thresholds) {
  if (!(thresholds.calibration_seconds > 0.0) || !(thresholds.false_alarms_per_hour > 0.0))
    return std::nullopt;
  CalibrationConfidence out;
  out.seconds = thresholds.calibration_seconds;
  out.confirmed_per_hour = 3.0 / out.seconds * 3600.0;
  out.needed_seconds = 3.0 / (thresholds.false_alarms_per_hour / 3600.0);
  out.extrapolated = thresholds.false_alarms_per_hour < out.confirmed_per_hour;
  return out;
}

}  // namespace dynid
