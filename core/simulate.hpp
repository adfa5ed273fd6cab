// Simulated data: the true model driven by a controller, sampled at a recording rate.
#pragma once

#include <cstdint>

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
};

/// Simulates `truth` from the controller's reference state at t = 0 for options.duration. Every
/// 1/record_rate seconds the controller computes a torque, the state, the torque and the exact
/// acceleration ddq = ABA(q, dq, tau) are recorded, and the torque is held for
/// step-sized integrator steps until the next sample; noise is added to the recorded q, dq, tau
/// only (never to the simulated state). Throws InputError when 1/record_rate is not a whole
/// multiple of step (to 1e-9 relative), a setting is non-positive or non-finite, the run would
/// record over 1e8 samples, take over 1e9 steps or need more memory than the process may use
/// (core/memory.hpp), or the controller has a different joint count;
/// NumericalError when the state becomes non-finite (names the time).
Trajectory simulate(const Model& truth, TrackingController& controller,
                    const SimulationOptions& options);

}  // namespace dynid
