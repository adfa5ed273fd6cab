// Simulated data: the true model driven by a controller, sampled at a recording rate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/controllers.hpp"
#include "core/integrators.hpp"
#include "core/trajectory.hpp"

namespace dynid {

struct SimulationOptions {
  double duration = 10.0;       // [s]
  double step = 1e-3;           // integration step [s]
  double record_rate = 1000.0;  // samples per second; the controller also runs at this rate
  IntegratorType integrator = IntegratorType::kRk4;
  double noise_q = 0.0;    // standard deviation of Gaussian noise added to recorded q [rad]
  double noise_dq = 0.0;   // ... to recorded dq [rad/s]
  double noise_tau = 0.0;  // ... to recorded tau [N m]
  std::uint64_t seed = 1;  // seeds the noise (std::mt19937_64)
  /// Stick-slip friction: a joint whose friction needs sign(dq) (Coulomb, asymmetry, Stribeck)
  /// stops at zero velocity and stays there while the friction that holds it, any value in its
  /// static band (staticFrictionBand), can; it breaks away when the torque on it leaves the band,
  /// with the band's edge as its friction; the truth's rest velocities are not used (a
  /// measurement's threshold, not physics). Off (the default): the friction is the law's at the
  /// step's dq (zero within the truth's rest velocities), which chatters by +-Fc about a resting
  /// joint, as the GC rollouts integrate it (so that the truth's rollouts reproduce its data, as in
  /// the paper).
  bool stiction = false;
};

/// An external disturbance over [start, start + duration): a torque on one joint, or a wrench on
/// one link (a force at its frame origin and a moment, both in base-frame coordinates). A short
/// duration makes an impulse, a long one a step.
struct Disturbance {
  double start = 0.0, duration = 0.0;  // [s]
  int joint = -1;                      // a joint torque [N m] on this joint (0-based), or
  double torque = 0.0;
  int link = -1;  // a wrench on this link (0-based body index) [N], [N m]
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
};

/// The joint torques J^T w of a wrench on link `link` (force at the link frame origin and moment,
/// base-frame coordinates) at configuration q (n entries). Throws InputError for a link out of
/// range. Overwrites data.liMi, data.oMj, data.oMi, data.f.
Eigen::VectorXd wrenchJointTorques(const Model& model, Data& data, const Eigen::VectorXd& q,
                                   int link, const Eigen::Vector3d& force,
                                   const Eigen::Vector3d& moment);

/// Simulates `truth` from the controller's reference state at t = 0 for options.duration. Every
/// 1/record_rate seconds the controller computes a torque, the state, the torque and the exact
/// acceleration ddq = ABA(q, dq, tau) are recorded, and the torque is held for
/// step-sized integrator steps until the next sample; noise is added to the recorded q, dq, tau
/// only (never to the simulated state). With options.stiction, a step that starts with a joint
/// within a velocity window of zero (what half its static band takes from its velocity in one
/// step) stops it there when its band can hold it (its acceleration zero, the mass matrix's
/// remaining block solved for the others), and so does a step across which its velocity changes
/// sign; the recorded dq and ddq are then the held ones. Throws
/// InputError when 1/record_rate is not a whole multiple of step (to 1e-9 relative), a setting is
/// non-positive or non-finite, the run would record over 1e8 samples, take over 1e9 steps or need
/// more memory than the process may use (core/memory.hpp), or the controller has a different joint
/// count; NumericalError when the state becomes non-finite (names the time). With `disturbances`,
/// each adds its joint torque to the controller's while active (evaluated at every integration
/// step; the recorded tau stays the controller's, the recorded ddq is the true one), and `applied`,
/// when given, receives the external joint torque at every sample (n x samples): the ground truth
/// of a collision detector. InputError also for a disturbance on a joint or link out of range, or a
/// non-finite or negative time.
Trajectory simulate(const Model& truth, TrackingController& controller,
                    const SimulationOptions& options,
                    const std::vector<Disturbance>& disturbances = {},
                    Eigen::MatrixXd* applied = nullptr);

}  // namespace dynid
