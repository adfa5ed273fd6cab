// Simulated PUMA logs with pushes for the monitor's tests (tests/monitor/): a tracking run with
// external joint torques applied, and one push.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/simulate.hpp"
#include "core/trajectory.hpp"
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

inline Disturbance jointPush(int joint, double torque, double start, double duration) {
  Disturbance d;
  d.joint = joint, d.torque = torque, d.start = start, d.duration = duration;
  return d;
}

}  // namespace dynid::test
