// Template bodies of ModelTpl's non-inline members; include only to instantiate a new Scalar.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

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
  parents_.push_back(parent);
  link_names.push_back(std::move(link_name));
  joint_names.push_back(std::move(joint_name));
  joint_types_.push_back(type);
  joint_placements_.push_back(joint_placement);
  body_placements_.push_back(body_placement);
  axes_.push_back(axis);
  inertias_.push_back(inertia);
  limits.push_back(joint_limits);
  drives_.push_back(drive);
  return index;
}

template <typename Scalar>
void ModelTpl<Scalar>::finalize() {
  using model_detail::value;
  const int n = numJoints();
  motion_subspaces_.assign(n, Vector6<Scalar>::Zero());
  frame_placements_.assign(n, Pose<Scalar>());
  axis_kinds_.assign(n, AxisKind::kGeneral);
  subspace_index_.assign(n, -1);
  has_frame_placement_.assign(n, 1);
  placement_permutation_.assign(n, -1);
  placement_shift_.assign(n, Vector3<Scalar>::Zero());
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(value(gravity_(i)))) throw InputError("model gravity is not finite");
  for (int i = 0; i < n; ++i) {
    const std::string who = "body '" + link_names[i] + "' (joint '" + joint_names[i] + "')";
    if (parents_[i] >= i) throw InputError(who + ": parent must come before the child");
    const double norm = value(axes_[i].norm());
    if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-9)
      throw InputError(who + ": joint axis must be a unit vector (norm " + std::to_string(norm) +
                       ")");
    if (!model_detail::allFinite(joint_placements_[i]) ||
        !model_detail::allFinite(body_placements_[i]))
      throw InputError(who + ": joint or body placement has a non-finite entry");
    const auto theta = toStandardVector(inertias_[i]);
    for (int k = 0; k < 10; ++k)
      if (!std::isfinite(value(theta(k))))
        throw InputError(who + ": inertial parameter " + std::string(kLinkParameterNames[k]) +
                         " is not finite");
    const DriveParameters<Scalar>& d = drives_[i];
    for (int k = 0; k < kDriveTermCount; ++k)
      if (!std::isfinite(value(d.term(k))))
        throw InputError(who + ": drive parameter " + std::string(kDriveParameterNames[k]) +
                         " is not finite");
    const Vector3<double> a(value(axes_[i].x()), value(axes_[i].y()), value(axes_[i].z()));
    if (a == Vector3<double>::UnitX()) axis_kinds_[i] = AxisKind::kX;
    if (a == Vector3<double>::UnitY()) axis_kinds_[i] = AxisKind::kY;
    if (a == Vector3<double>::UnitZ()) axis_kinds_[i] = AxisKind::kZ;
    // Joint frame i in the parent's joint frame at q_i = 0.
    frame_placements_[i] = parents_[i] < 0 ? joint_placements_[i]
                                           : body_placements_[parents_[i]] * joint_placements_[i];
    has_frame_placement_[i] = !model_detail::isIdentity(frame_placements_[i]);
    const bool prismatic = joint_types_[i] == JointType::kPrismatic;
    if (prismatic)
      motion_subspaces_[i].template tail<3>() = axes_[i];
    else
      motion_subspaces_[i].template head<3>() = axes_[i];
    if (axis_kinds_[i] != AxisKind::kGeneral)
      subspace_index_[i] = static_cast<int>(axis_kinds_[i]) + (prismatic ? 3 : 0);
    const int k = model_detail::signedPermutationIndex(frame_placements_[i].rotation);
    if (permuted_placements_ && !prismatic && axis_kinds_[i] == AxisKind::kZ && k >= 0) {
      placement_permutation_[i] = k;
      for (int j = 0; j < 3; ++j)  // (Pi^T t)_j = t_{pi^-1(j)}
        placement_shift_[i](kAxisPermutations[k][j]) =
            Scalar(kAxisPermutationSigns[k]) * frame_placements_[i].translation(j);
    }
  }
  updateFrameInertias();
}

template <typename Scalar>
VectorX<Scalar> ModelTpl<Scalar>::standardParameters() const {
  const ParameterLayout layout = parameterLayout();
  VectorX<Scalar> theta(layout.size());
  for (int i = 0; i < numJoints(); ++i) {
    theta.template segment<10>(layout.linkIndex(i, 0)) = toStandardVector(inertias_[i]);
    for (int k = 0; k < kDriveTermCount; ++k)
      if (drive_terms_.has(k)) theta(layout.driveIndex(i, k)) = drives_[i].term(k);
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
    inertias_[i] = fromStandardVector(theta.template segment<10>(layout.linkIndex(i, 0)));
    for (int k = 0; k < kDriveTermCount; ++k)
      if (drive_terms_.has(k)) drives_[i].term(k) = theta(layout.driveIndex(i, k));
  }
  updateFrameInertias();
}

template <typename Scalar>
void ModelTpl<Scalar>::checkIndex(int i, const char* what) const {
  if (i < 0 || i >= numJoints())
    throw InputError(std::string(what) + " index " + std::to_string(i) +
                     " is out of range: model '" + name + "' has " + std::to_string(numJoints()) +
                     " bodies and joints");
}

template <typename Scalar>
void ModelTpl<Scalar>::setLinkInertia(int i, const RigidInertia<Scalar>& inertia) {
  checkIndex(i, "link");
  inertias_[i] = inertia;
  if (frame_inertias_.size() == inertias_.size()) updateFrameInertia(i);
}

template <typename Scalar>
void ModelTpl<Scalar>::setLinkInertias(const std::vector<RigidInertia<Scalar>>& inertias) {
  if (static_cast<int>(inertias.size()) != numJoints())
    throw InputError(std::to_string(inertias.size()) + " link inertias given, model '" + name +
                     "' has " + std::to_string(numJoints()) + " links");
  inertias_ = inertias;
  if (finalized()) updateFrameInertias();
}

template <typename Scalar>
void ModelTpl<Scalar>::setGravity(const Vector3<Scalar>& g) {
  double norm2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double gi = model_detail::value(g(i));
    if (!std::isfinite(gi))
      throw InputError("gravity: entry " + std::to_string(i) + " is not finite");
    norm2 += gi * gi;
  }
  if (std::sqrt(norm2) > kMaxGravity)
    throw InputError("gravity: |g| = " + std::to_string(std::sqrt(norm2)) +
                     " m/s^2 is beyond 1e3 m/s^2");
  gravity_ = g;
}

template <typename Scalar>
void ModelTpl<Scalar>::setDrive(int i, const DriveParameters<Scalar>& drive) {
  checkIndex(i, "joint");
  drives_[i] = drive;
}

template <typename Scalar>
void ModelTpl<Scalar>::setJointPlacement(int i, const Pose<Scalar>& placement) {
  checkIndex(i, "joint");
  const bool was_finalized = finalized();
  joint_placements_[i] = placement;
  if (was_finalized) finalize();
}

template <typename Scalar>
void ModelTpl<Scalar>::setBodyPlacement(int i, const Pose<Scalar>& placement) {
  checkIndex(i, "body");
  const bool was_finalized = finalized();
  body_placements_[i] = placement;
  if (was_finalized) finalize();
}

template <typename Scalar>
void ModelTpl<Scalar>::setPermutedPlacements(bool enabled) {
  const bool was_finalized = finalized();
  permuted_placements_ = enabled;
  if (was_finalized) finalize();
}

namespace model_detail {
/// Equal entries: exactly for double, whose caches finalize() recomputes along the same path; to
/// 1e-12 relative for another scalar (a Jet model cast from a double one carries caches computed
/// in double, where Eigen's vectorised products sum in another order than the Jet's scalar ones,
/// so the last bit may differ). A stale cache differs by far more.
template <typename Scalar>
bool sameEntry(const Scalar& a, const Scalar& b) {
  if constexpr (std::is_same_v<Scalar, double>) {
    return a == b;
  } else {
    const double x = value(a), y = value(b);
    return std::abs(x - y) <= 1e-12 * (1.0 + std::max(std::abs(x), std::abs(y)));
  }
}
template <typename A, typename B>
bool same(const A& a, const B& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index k = 0; k < a.size(); ++k)
    if (!sameEntry(a.data()[k], b.data()[k])) return false;
  return true;
}
template <typename Scalar>
bool same(const Pose<Scalar>& a, const Pose<Scalar>& b) {
  return same(a.rotation, b.rotation) && same(a.translation, b.translation);
}
template <typename Scalar>
bool same(const RigidInertia<Scalar>& a, const RigidInertia<Scalar>& b) {
  return sameEntry(a.mass, b.mass) && same(a.first_moment, b.first_moment) &&
         same(a.inertia, b.inertia);
}
template <typename T>
bool sameAll(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      if (a[i] != b[i]) return false;
    } else if (!same(a[i], b[i])) {
      return false;
    }
  }
  return true;
}
}  // namespace model_detail

template <typename Scalar>
bool ModelTpl<Scalar>::cachesAreCurrent() const {
  using model_detail::sameAll;
  ModelTpl fresh = *this;
  try {
    fresh.finalize();
  } catch (const InputError&) {
    return false;
  }
  return sameAll(frame_placements_, fresh.frame_placements_) &&
         sameAll(frame_inertias_, fresh.frame_inertias_) &&
         sameAll(frame_inertia_matrices_, fresh.frame_inertia_matrices_) &&
         sameAll(motion_subspaces_, fresh.motion_subspaces_) &&
         sameAll(axis_kinds_, fresh.axis_kinds_) &&
         sameAll(subspace_index_, fresh.subspace_index_) &&
         sameAll(has_frame_placement_, fresh.has_frame_placement_) &&
         sameAll(placement_permutation_, fresh.placement_permutation_) &&
         sameAll(placement_shift_, fresh.placement_shift_);
}

}  // namespace dynid
