// The PUMA 560's and the Panda's kinematics as Pinocchio models, for the side-by-side benchmarks
// (scripts/pinocchio-bench.sh). Joint placements from the same DH tables as dynid's built-in robots
// (data/puma560.cpp: standard DH; data/panda.cpp: modified DH); the inertias are Pinocchio's
// random ones, since no timed algorithm's cost depends on their values.
#pragma once

#include <cmath>
#include <numbers>
#include <string>

#include "pinocchio/multibody/model.hpp"

namespace peers {

/// Rotation about x by alpha for the DH tables' alphas (0 and +-pi/2): exact entries.
inline Eigen::Matrix3d rotX(double alpha) {
  const double ca = alpha == 0.0 ? 1.0 : 0.0, sa = alpha > 0 ? 1.0 : (alpha < 0 ? -1.0 : 0.0);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
  return r;
}

/// Six revolute z joints; joint i + 1 sits at Rx(alpha_i) Tx(a_i) Tz(d_i) in joint i's frame
/// (standard DH: the link's placement follows the joint's rotation).
inline pinocchio::Model puma() {
  struct Dh {
    double d, a, alpha;
  };
  const double pi = std::numbers::pi;
  const Dh dh[6] = {{0.0, 0.0, pi / 2},    {0.0, 0.4318, 0.0},  {0.15005, 0.0203, -pi / 2},
                    {0.4318, 0.0, pi / 2}, {0.0, 0.0, -pi / 2}, {0.0, 0.0, 0.0}};
  pinocchio::Model model;
  pinocchio::JointIndex parent = 0;
  pinocchio::SE3 placement = pinocchio::SE3::Identity();
  for (int i = 0; i < 6; ++i) {
    parent = model.addJoint(parent, pinocchio::JointModelRZ(), placement,
                            "joint" + std::to_string(i + 1));
    model.appendBodyToJoint(parent, pinocchio::Inertia::Random(), pinocchio::SE3::Identity());
    placement = pinocchio::SE3(rotX(dh[i].alpha), Eigen::Vector3d(dh[i].a, 0.0, dh[i].d));
  }
  model.gravity.linear() << 0, 0, -9.81;
  return model;
}

/// Seven revolute z joints; joint i sits at Rx(alpha_{i-1}) Tx(a_{i-1}) Tz(d_i) in joint i-1's
/// frame (modified DH, Franka's table).
inline pinocchio::Model panda() {
  const double pi = std::numbers::pi;
  const double a[7] = {0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088};
  const double d[7] = {0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.0};
  const double alpha[7] = {0.0, -pi / 2, pi / 2, pi / 2, -pi / 2, pi / 2, pi / 2};
  pinocchio::Model model;
  pinocchio::JointIndex parent = 0;
  for (int i = 0; i < 7; ++i) {
    const Eigen::Matrix3d r = rotX(alpha[i]);
    const pinocchio::SE3 placement(
        r, Eigen::Vector3d(a[i], 0.0, 0.0) + r * Eigen::Vector3d(0, 0, d[i]));
    parent = model.addJoint(parent, pinocchio::JointModelRZ(), placement,
                            "joint" + std::to_string(i + 1));
    model.appendBodyToJoint(parent, pinocchio::Inertia::Random(), pinocchio::SE3::Identity());
  }
  model.gravity.linear() << 0, 0, -9.81;
  return model;
}

}  // namespace peers
