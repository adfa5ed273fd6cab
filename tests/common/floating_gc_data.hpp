// A floating robot's recorded motion for the GC error's tests (search/floating/): ANYmal C (or
// any floating model) hung from a force-torque sensor on its base, its joints swinging; the
// torques and the sensor's wrench are the ones floatingRnea says the motion needs.
#pragma once

#include <cmath>
#include <numbers>

#include "core/floating/floating_rnea.hpp"
#include "search/floating/floating_gc.hpp"

namespace dynid::test {

/// The sensor: off the base origin and turned, so its wrench is not the base's.
inline Contact sensor() {
  Contact c;
  c.name = "support";
  c.body = -1;
  c.kind = Contact::Kind::kFrame;
  c.placement.translation = Eigen::Vector3d(0.1, -0.05, 0.2);
  c.placement.rotation = rotationFromRpy(0.3, -0.2, 0.5);
  return c;
}

/// Sample k's torques and sensor wrench from the generalized force g inverse dynamics gives: the
/// base wrench (n_b, f_b) the motion needs is the sensor's, moved: f_b = R f, n_b = R n + p x f_b.
inline void record(FloatingGcData& d, int k, const Eigen::VectorXd& g) {
  const Pose<double>& X = d.contacts[0].placement;
  d.tau.col(k) = g.tail(d.tau.rows());
  const Eigen::Vector3d f = g.segment<3>(3);
  d.wrenches[0].col(k) << X.rotation.transpose() * (g.head<3>() - cross(X.translation, f)),
      X.rotation.transpose() * f;
}

/// `seconds` of the suspended motion sampled at `rate` [Hz]: the base still in a tilted
/// orientation, each joint q0 + 0.3 sin(2 pi f t + phase), the torques and the sensor's wrench (in
/// its axes, about its origin) from inverse dynamics.
inline FloatingGcData suspended(const FloatingModel& model, double rate, double seconds) {
  const int n = model.numJoints(), samples = static_cast<int>(std::round(rate * seconds)) + 1;
  FloatingGcData d;
  d.contacts = {sensor()};
  d.time.resize(samples);
  d.orientation.resize(4, samples);
  d.twist.setZero(6, samples);
  d.q.resize(n, samples), d.dq.resize(n, samples), d.tau.resize(n, samples);
  d.wrenches = {Eigen::MatrixXd(6, samples)};
  FloatingData data(model);
  BaseMotion base;
  const Eigen::Vector4d tilt = Eigen::Vector4d(0.95, 0.2, -0.1, 0.15).normalized();
  base.rotation = baseRotation(tilt);
  for (int k = 0; k < samples; ++k) {
    const double t = k / rate;
    Eigen::VectorXd ddq(n);
    for (int i = 0; i < n; ++i) {
      const double w = 2.0 * std::numbers::pi * (0.5 + 0.1 * i), phase = 0.7 * i;
      d.q(i, k) = 0.1 * i - 0.5 + 0.3 * std::sin(w * t + phase);
      d.dq(i, k) = 0.3 * w * std::cos(w * t + phase);
      ddq[i] = -0.3 * w * w * std::sin(w * t + phase);
    }
    d.time[k] = t;
    d.orientation.col(k) = tilt;
    record(d, k, floatingRnea(model, data, base, d.q.col(k), d.dq.col(k), ddq));
  }
  return d;
}

}  // namespace dynid::test
