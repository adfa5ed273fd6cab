// A payload's body in the forms vendors ask for: mass, centre of mass, principal moments and axes
// (PrincipalBody), and the rotation conventions of KUKA (A, B, C) and ABB (quaternions).
#pragma once

#include <Eigen/Core>

#include "core/spatial.hpp"
#include "identifiability/payload.hpp"

namespace dynid {

/// The body as mass, centre of mass, principal moments and axes: the axes are the eigenvectors of
/// the inertia about the centre of mass, ordered and signed so that the rotation (columns, det +1)
/// is the one nearest the attachment frame's axes (largest trace among the 24 choices).
struct PrincipalBody {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
/// Throws InputError for a mass <= 0.
PrincipalBody principalBody(const Vector10d& standard);
/// The standard parameters of a principal body (the inverse).
Vector10d standardFromPrincipal(const PrincipalBody& body);

/// KUKA's A, B, C [rad]: R = Rz(A) Ry(B) Rx(C) (rotation about Z, then the new Y, then the new X).
Eigen::Vector3d kukaAbc(const Eigen::Matrix3d& rotation);
Eigen::Matrix3d rotationFromKukaAbc(const Eigen::Vector3d& abc);
/// ABB's quaternion [q1, q2, q3, q4] (q1 the scalar part, q1 >= 0) of a rotation, and back.
Eigen::Vector4d abbQuaternion(const Eigen::Matrix3d& rotation);
Eigen::Matrix3d rotationFromAbbQuaternion(const Eigen::Vector4d& q);

}  // namespace dynid
