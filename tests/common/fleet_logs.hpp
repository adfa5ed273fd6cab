// Logs of a fleet's robots for the fleet's tests and benchmark: a robot's torques along a seeded
// Fourier motion with stops, from its regressor and parameters (no controller: the motion is the
// reference itself), with noise on the torques and the velocities.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "analysis/runs/simulate.hpp"
#include "core/controllers.hpp"
#include "core/data.hpp"
#include "core/model.hpp"
#include "core/regressor.hpp"
#include "core/trajectory.hpp"

namespace dynid::test {

/// A log of `truth` at `rate` Hz: a seeded Fourier motion (0.1 Hz, 5 harmonics, 0.7 rad about the
/// middle of the limits) with stops (4 s moves, 2 s holds, 0.5 s ramps), its torques from the
/// regressor; Gaussian noise of `noise_tau` on tau and `noise_dq` on dq. With `stribeck` (per
/// joint Fs), a Stribeck torque Fs sign(dq) exp(-(dq / 0.05)^2) on top, which a model without
/// that drive term does not carry (a model error at every stop and reversal).
inline Trajectory fleetLog(const Model& truth, double seconds, std::uint64_t seed, double rate,
                           double noise_tau = 0.1, double noise_dq = 1e-3,
                           const Eigen::VectorXd* stribeck = nullptr) {
  const int n = truth.numJoints();
  const FourierSeries f =
      randomFourier(defaultCentre(truth), Eigen::VectorXd::Constant(n, 0.7), 0.1, 5, seed);
  const Reference ref = f;
  const Pauses pauses{4.0, 2.0, 0.5};
  const int samples = static_cast<int>(seconds * rate);
  Trajectory out;
  out.resize(n, samples);
  Data data(truth);
  const Eigen::VectorXd theta = truth.standardParameters();
  std::mt19937_64 rng(seed ^ 0x5eedULL);
  std::normal_distribution<double> noise;
  Eigen::VectorXd q(n), dq(n), ddq(n);
  for (int k = 0; k < samples; ++k) {
    const double t = k / rate;
    double at = 0.0, speed = 0.0, speed_rate = 0.0;  // the reference's time and its derivatives
    pauses.warp(t, at, speed, speed_rate);
    evaluateReference(ref, at, q, dq, ddq);
    ddq = ddq * speed * speed + dq * speed_rate;
    dq *= speed;
    out.time[k] = t;
    out.q.col(k) = q;
    out.dq.col(k) = dq;
    out.ddq.col(k) = ddq;
    out.tau.col(k) = jointTorqueRegressor(truth, data, q, dq, ddq) * theta;
    if (stribeck)
      for (int j = 0; j < n; ++j)
        out.tau(j, k) += (*stribeck)[j] * ((dq[j] > 0.0) - (dq[j] < 0.0)) *
                         std::exp(-(dq[j] / 0.05) * (dq[j] / 0.05));
    for (int j = 0; j < n; ++j) {
      out.tau(j, k) += noise_tau * noise(rng);
      out.dq(j, k) += noise_dq * noise(rng);
    }
  }
  return out;
}

}  // namespace dynid::test
