// Simulated PUMA logs with pushes for the monitor's tests (tests/monitor/): a tracking run with
// external joint torques applied, and one push; thresholds without arm states (version 1) or
// without moving regimes (version 2).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/records/monitor_record.hpp"
#include "core/simulate.hpp"
#include "core/trajectory.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::test {

inline Trajectory pushedPuma(const Model& model, double duration,
                             const std::vector<Disturbance>& pushes,
                             Eigen::MatrixXd* applied = nullptr, double noise = 0.0) {
  TrackingController controller = pumaSinusoidController(model, 0.4, 0.2, 0.6);
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = noise;
  options.noise_dq = noise * 0.02;
  options.seed = 7;
  return simulate(model, controller, options, pushes, applied);
}

/// `nominal` with a Stribeck (breakaway) term half its Coulomb friction on every joint, which a
/// model of its own drive terms does not carry (the monitor's friction the identification lacks).
inline Model withStribeck(const Model& nominal) {
  Model out = nominal;
  DriveTerms terms = nominal.driveTerms();
  terms.mask |= DriveTerms::of({DriveTerm::kStribeck}).mask;
  out.setDriveTerms(terms);
  for (int j = 0; j < out.numJoints(); ++j) {
    DriveParameters<double> d = nominal.drives()[j];
    d[DriveTerm::kStribeck] = 0.5 * d[DriveTerm::kCoulomb];
    out.setDrive(j, d);
  }
  return out;
}

inline Disturbance jointPush(int joint, double torque, double start, double duration) {
  Disturbance d;
  d.joint = joint, d.torque = torque, d.start = start, d.duration = duration;
  return d;
}

/// `t` as a version 1 thresholds file (one threshold per joint, no arm states: the thresholds of
/// the release before them), written to `path`; returns it.
inline std::string writeThresholdsWithoutStates(const MonitorThresholds& t,
                                                const std::string& path) {
  const nlohmann::json document = {
      {"schema_version", 1},
      {"kind", "dynid.monitor_thresholds"},
      {"robot", t.robot},
      {"joints", t.joint_names},
      {"residual", t.residual == MonitorResidual::kDirect ? "direct" : "observer"},
      {"gain", std::vector<double>(t.gain.begin(), t.gain.end())},
      {"source", "previous"},
      {"thresholds", std::vector<double>(t.values.begin(), t.values.end())},
      {"false_alarms_per_hour", t.false_alarms_per_hour}};
  writeFileAtomically(path, document.dump());
  return path;
}

/// `t` as a version 2 thresholds file (one moving threshold per joint and the arm states, no
/// moving regimes: the thresholds of the release before them), written to `path`; returns it.
inline std::string writeThresholdsWithoutRegimes(const MonitorThresholds& t,
                                                 const std::string& path) {
  const auto list = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.begin(), v.end());
  };
  nlohmann::json document = {
      {"schema_version", 2},
      {"kind", "dynid.monitor_thresholds"},
      {"robot", t.robot},
      {"joints", t.joint_names},
      {"residual", t.residual == MonitorResidual::kDirect ? "direct" : "observer"},
      {"gain", list(t.gain)},
      {"source", "previous"},
      {"thresholds", list(t.values)},
      {"false_alarms_per_hour", t.false_alarms_per_hour},
      {"rest_velocity", list(t.rest_velocity)},
      {"thresholds_at_rest", nullptr}};
  if (t.values_at_rest.size() > 0) {
    document["thresholds_at_rest"] = list(t.values_at_rest);
    document["rest_seconds"] = t.rest_seconds;
  }
  writeFileAtomically(path, document.dump());
  return path;
}

}  // namespace dynid::test
