// Template bodies of ModelTpl's non-inline members; include only to instantiate a new Scalar.
#pragma once

#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/model.hpp"

namespace dynid {

namespace model_detail {
template <typename Scalar>
double value(const Scalar& x) {
  if constexpr (std::is_arithmetic_v<Scalar>) {
    return static_cast<double>(x);
  } else {
    return x.a;  // ceres::Jet and similar dual numbers
  }
}
template <typename Scalar>
bool isIdentity(const Pose<Scalar>& pose) {
  for (int r = 0; r < 3; ++r) {
    if (value(pose.translation(r)) != 0.0) return false;
    for (int c = 0; c < 3; ++c)
      if (value(pose.rotation(r, c)) != (r == c ? 1.0 : 0.0)) return false;
  }
  return true;
}
template <typename Scalar>
bool allFinite(const Pose<Scalar>& pose) {
  for (int r = 0; r < 3; ++r) {
    if (!std::isfinite(value(pose.translation(r)))) return false;
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(value(pose.rotation(r, c)))) return false;
  }
  return true;
}
/// The index into kAxisPermutations of the permutation pi with rotation(a, pi(a)) = +-1 and every
/// other entry exactly 0, or -1 when the rotation is not such a signed permutation (or, for a
/// dual number, carries a derivative: ABA's permuted path treats it as a constant).
template <typename Scalar>
int signedPermutationIndex(const Matrix3<Scalar>& rotation) {
  if constexpr (!std::is_arithmetic_v<Scalar>) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (!rotation(a, b).v.isZero()) return -1;
  }
  for (int k = 0; k < 6; ++k) {
    bool match = true;
    for (int a = 0; a < 3 && match; ++a)
      for (int b = 0; b < 3 && match; ++b) {
        const double x = value(rotation(a, b));
        match = b == kAxisPermutations[k][a] ? (x == 1.0 || x == -1.0) : x == 0.0;
      }
    if (match) return k;
  }
  return -1;
}
}  // namespace model_detail

const char* jointTypeName(JointType type);

template <typename Scalar>
int ModelTpl<Scalar>::addBody(int parent, std::string link_name, std::string joint_name,
                              JointType type, const Pose<Scalar>& joint_placement,
                              const Vector3<Scalar>& axis, const Pose<Scalar>& body_placement,
                              const RigidInertia<Scalar>& inertia, const JointLimits& joint_limits,
                              const DriveParameters<Scalar>& drive) {
  const int index = numJoints();
  if (parent < -1 || parent >= index)
    throw InputError("body '" + link_name + "': parent index " + std::to_string(parent) +
                     " is not an existing body (bodies must be added parents first)");
  parents.push_back(parent);
  link_names.push_back(std::move(link_name));
  joint_names.push_back(std::move(joint_name));
  joint_types.push_back(type);
  joint_placements.push_back(joint_placement);
  body_placements.push_back(body_placement);
  axes.push_back(axis);
  inertias.push_back(inertia);
  limits.push_back(joint_limits);
  drives.push_back(drive);
  return index;
}

template <typename Scalar>
void ModelTpl<Scalar>::finalize() {
  using model_detail::value;
  const int n = numJoints();
  motion_subspaces.assign(n, Vector6<Scalar>::Zero());
  frame_placements.assign(n, Pose<Scalar>());
  axis_kinds.assign(n, AxisKind::kGeneral);
  subspace_index.assign(n, -1);
  has_frame_placement.assign(n, 1);
  placement_permutation.assign(n, -1);
  placement_shift.assign(n, Vector3<Scalar>::Zero());
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(value(gravity(i)))) throw InputError("model gravity is not finite");
  for (int i = 0; i < n; ++i) {
    const std::string who = "body '" + link_names[i] + "' (joint '" + joint_names[i] + "')";
    if (parents[i] >= i) throw InputError(who + ": parent must come before the child");
    const double norm = value(axes[i].norm());
    if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-9)
      throw InputError(who + ": joint axis must be a unit vector (norm " + std::to_string(norm) +
                       ")");
    if (!model_detail::allFinite(joint_placements[i]) ||
        !model_detail::allFinite(body_placements[i]))
      throw InputError(who + ": joint or body placement has a non-finite entry");
    const auto theta = toStandardVector(inertias[i]);
    for (int k = 0; k < 10; ++k)
      if (!std::isfinite(value(theta(k))))
        throw InputError(who + ": inertial parameter " + std::string(kLinkParameterNames[k]) +
                         " is not finite");
    const DriveParameters<Scalar>& d = drives[i];
    if (!std::isfinite(value(d.rotor_inertia)) || !std::isfinite(value(d.viscous)) ||
        !std::isfinite(value(d.coulomb)) || !std::isfinite(value(d.offset)))
      throw InputError(who + ": a drive parameter is not finite");
    const Vector3<double> a(value(axes[i].x()), value(axes[i].y()), value(axes[i].z()));
    if (a == Vector3<double>::UnitX()) axis_kinds[i] = AxisKind::kX;
    if (a == Vector3<double>::UnitY()) axis_kinds[i] = AxisKind::kY;
    if (a == Vector3<double>::UnitZ()) axis_kinds[i] = AxisKind::kZ;
    // Joint frame i in the parent's joint frame at q_i = 0.
    frame_placements[i] =
        parents[i] < 0 ? joint_placements[i] : body_placements[parents[i]] * joint_placements[i];
    has_frame_placement[i] = !model_detail::isIdentity(frame_placements[i]);
    const bool prismatic = joint_types[i] == JointType::kPrismatic;
    if (prismatic)
      motion_subspaces[i].template tail<3>() = axes[i];
    else
      motion_subspaces[i].template head<3>() = axes[i];
    if (axis_kinds[i] != AxisKind::kGeneral)
      subspace_index[i] = static_cast<int>(axis_kinds[i]) + (prismatic ? 3 : 0);
    const int k = model_detail::signedPermutationIndex(frame_placements[i].rotation);
    if (!prismatic && axis_kinds[i] == AxisKind::kZ && k >= 0) {
      placement_permutation[i] = k;
      for (int j = 0; j < 3; ++j)  // (Pi^T t)_j = t_{pi^-1(j)}
        placement_shift[i](kAxisPermutations[k][j]) =
            Scalar(kAxisPermutationSigns[k]) * frame_placements[i].translation(j);
    }
  }
  updateFrameInertias();
  if (offsets_enabled && !drives_enabled)
    throw InputError("model '" + name + "': offsets (Fo) need drives enabled");
}

template <typename Scalar>
VectorX<Scalar> ModelTpl<Scalar>::standardParameters() const {
  const ParameterLayout layout = parameterLayout();
  VectorX<Scalar> theta(layout.size());
  for (int i = 0; i < numJoints(); ++i) {
    theta.template segment<10>(layout.linkIndex(i, 0)) = toStandardVector(inertias[i]);
    if (!drives_enabled) continue;
    theta(layout.driveIndex(i, 0)) = drives[i].rotor_inertia;
    theta(layout.driveIndex(i, 1)) = drives[i].viscous;
    theta(layout.driveIndex(i, 2)) = drives[i].coulomb;
    if (offsets_enabled) theta(layout.driveIndex(i, 3)) = drives[i].offset;
  }
  return theta;
}

template <typename Scalar>
void ModelTpl<Scalar>::setStandardParameters(const VectorX<Scalar>& theta) {
  const ParameterLayout layout = parameterLayout();
  if (theta.size() != layout.size())
    throw InputError("parameter vector has " + std::to_string(theta.size()) + " entries, model '" +
                     name + "' has " + std::to_string(layout.size()));
  for (int i = 0; i < numJoints(); ++i) {
    inertias[i] = fromStandardVector(theta.template segment<10>(layout.linkIndex(i, 0)));
    if (!drives_enabled) continue;
    drives[i].rotor_inertia = theta(layout.driveIndex(i, 0));
    drives[i].viscous = theta(layout.driveIndex(i, 1));
    drives[i].coulomb = theta(layout.driveIndex(i, 2));
    if (offsets_enabled) drives[i].offset = theta(layout.driveIndex(i, 3));
  }
  updateFrameInertias();
}

}  // namespace dynid
