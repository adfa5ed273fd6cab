// Denavit-Hartenberg models: a robot's kinematics as its datasheet gives them, one row per joint,
// in the standard convention or the modified one (Craig), and each link's parameters in its DH
// link frame.
//
// Standard DH (joint i turns about z_{i-1}; link frame i at the link's distal end):
//     T(i-1 -> i) = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
// Modified DH (joint i turns about z_i; a and alpha of row i are a_{i-1}, alpha_{i-1}):
//     T(i-1 -> i) = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)
// A revolute joint's angle is theta_i = q_i + theta_offset_i; a prismatic joint's length is
// d_i = q_i + d (d the row's d). Quarter-turn angles (within 1e-12 rad of a multiple of pi/2) are
// written with exact 0 and +-1 entries, so a DH robot takes ABA's permuted transform path.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"

namespace dynid {

enum class DhConvention { kStandard, kModified };
/// "standard" or "modified".
const char* dhConventionName(DhConvention convention);

/// One DH row: a joint and the link it moves.
struct DhRow {
  std::string joint_name, link_name;
  JointType type = JointType::kRevolute;
  double a = 0.0, d = 0.0, alpha = 0.0, theta_offset = 0.0;  // [m], [m], [rad], [rad]
  JointLimits limits;
  RigidInertia<double> inertia;  // in the DH link frame, about its origin
  DriveParameters<double> drive;
};

struct DhModel {
  std::string name;
  DhConvention convention = DhConvention::kStandard;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  DriveTerms drive_terms;
  std::vector<DhRow> rows;  // joints 1..n, each the child of the previous one (a serial chain)
};

/// The chain as a dynid Model: joint placements and body placements from the rows, each link's
/// parameters in its DH frame. Throws InputError for non-finite entries (naming the joint) and
/// what Model::finalize throws.
Model modelFromDh(const DhModel& dh);

/// The rotation about x (or z) by `angle` [rad], exact at multiples of pi/2.
Eigen::Matrix3d dhRotationX(double angle);
Eigen::Matrix3d dhRotationZ(double angle);

/// A link's inertia from its mass [kg], centre of mass c [m] and inertia about the centre of mass
/// (link axes) [kg m^2]: first moment m c, inertia about the origin I_c + m ([c]x)^T [c]x.
RigidInertia<double> inertiaFromCom(double mass, const Eigen::Vector3d& com,
                                    const Eigen::Matrix3d& inertia_about_com);

}  // namespace dynid
