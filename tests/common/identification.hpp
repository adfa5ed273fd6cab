// Shared by the identification tests: the PUMA's structural base parameters and an exciting
// trajectory for it. Header-only, so that only tests linking dynid::identifiability include it.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/observation.hpp"

namespace dynid::test {

/// Base parameters of `model` from 150 seeded random states, default preference.
inline BaseParameters pumaBase(const Model& model) {
  const ParameterLayout layout = model.parameterLayout();
  return computeBaseParameters(observationFromRandomStates(model, 150, 1).W,
                               standardParameterNames(layout), 0.0,
                               defaultPreference(layout.num_links, layout.perLink()));
}

/// A well-exciting PUMA trajectory: sinusoids at distinct frequencies around qn (joint 3 away from
/// its limit), with torque noise of standard deviation `noise_tau` [N m].
inline Trajectory pumaTrajectory(const Model& model, double duration, double noise_tau,
                                 std::uint64_t seed, double frequency_scale = 1.0) {
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.q0[2] = 0.5 * M_PI;
  r.amplitude.resize(6);
  r.amplitude << 1.2, 0.8, 0.9, 1.5, 1.2, 1.5;
  r.frequency = Eigen::VectorXd::LinSpaced(6, 0.23, 0.71) * frequency_scale;
  r.phase = Eigen::VectorXd::LinSpaced(6, 0.0, 2.5);
  TrackingController controller(model, r, defaultGains(model, r.q0, 8.0),
                                Eigen::VectorXd::Constant(6, 1e9));
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = noise_tau;
  options.seed = seed;
  return simulate(model, controller, options);
}

}  // namespace dynid::test
