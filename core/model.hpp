// The kinematic tree and its parameters. A Model is built once (addBody, then finalize) and then
// only read: algorithms take it by const reference and put every result in a Data (data.hpp).
//
// Bodies are numbered 0..n-1 in topological order (parent index < child index); parent -1 is the
// fixed base. Every body has exactly one joint with one degree of freedom connecting it to its
// parent (fixed joints are merged into the parent body by the loaders), so n bodies = n joints =
// n entries of q, dq, ddq and tau. Joint i places body i in its parent's frame as
//     liMi(q_i) = joint_placement_i * J(q_i) * body_placement_i
// where J is a rotation about `axis` (revolute, continuous) or a translation along it (prismatic).
// URDF models have body_placement = identity; standard Denavit-Hartenberg models (joint i turns
// about z_{i-1}, frame i at the distal end) have joint_placement = identity and body_placement =
// Tz(d) Tx(a) Rx(alpha), so each link's parameters stay in its DH frame.
//
// Symbols: q joint positions [rad or m], dq velocities, ddq accelerations, tau joint torques
// [N m or N], theta the standard parameter vector (parameters.hpp).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "core/parameters.hpp"
#include "core/spatial.hpp"

namespace dynid {

enum class JointType { kRevolute, kContinuous, kPrismatic };

/// "revolute", "continuous" or "prismatic".
const char* jointTypeName(JointType type);

struct JointLimits {
  double lower = -std::numeric_limits<double>::infinity();  // [rad or m]
  double upper = std::numeric_limits<double>::infinity();
  double velocity = std::numeric_limits<double>::infinity();      // [rad/s or m/s]
  double acceleration = std::numeric_limits<double>::infinity();  // [rad/s^2 or m/s^2]
  double effort = std::numeric_limits<double>::infinity();        // [N m or N]
};

/// Joint-side drive parameters: one value per row of the drive-term table (core/drive_terms.hpp),
/// in its units, whether or not the model enables the term (a disabled term's value is kept but
/// does not act). All zero by default.
template <typename Scalar>
struct DriveParameters {
  std::array<Scalar, kDriveTermCount> values;

  DriveParameters() { values.fill(Scalar(0)); }
  /// Term k (kDriveTermTable's row order: Ia, Fv, Fc, Fo, Fa, Fs).
  Scalar& term(int k) { return values[static_cast<std::size_t>(k)]; }
  const Scalar& term(int k) const { return values[static_cast<std::size_t>(k)]; }
  Scalar& operator[](DriveTerm t) { return term(static_cast<int>(t)); }
  const Scalar& operator[](DriveTerm t) const { return term(static_cast<int>(t)); }
};

/// How a joint's axis is stored, so the hot path can skip Rodrigues' formula for unit axes.
enum class AxisKind { kX, kY, kZ, kGeneral };

/// The six permutations of (0, 1, 2) in lexicographic order, and their determinants.
inline constexpr int kAxisPermutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                                {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
inline constexpr int kAxisPermutationSigns[6] = {1, -1, -1, 1, 1, -1};

/// A robot model, sealed: the kinematic structure and the inertial and drive parameters are
/// written only through addBody (before finalize) and the parameter setters, which refresh the
/// derived joint-frame caches, so no public call can leave a cache stale (Pinocchio's route: the
/// caches are private and read through const accessors). Gravity and the drive terms are set
/// through setGravity and setDriveTerms (a Data's regressor width follows the drive terms, and
/// checkData compares it). `name`, the names and `limits` feed no cache and stay plain fields.
template <typename Scalar>
class ModelTpl {
 public:
  std::string name;
  std::vector<std::string> link_names;
  std::vector<std::string> joint_names;
  std::vector<JointLimits> limits;
  /// Each joint's rest velocity [rad/s or m/s], >= 0: |dq| at or below it is "at rest", where the
  /// drive terms that need sign(dq) are static friction of point value zero (drive_terms.hpp).
  /// Measured from a log's velocity noise (analysis/logs/rest.hpp); empty (every joint 0: only an
  /// exact zero is at rest) by default. It feeds no cache.
  std::vector<double> rest_velocities;
  /// Joint i's rest velocity (0 when rest_velocities is empty).
  double restVelocity(int i) const {
    return rest_velocities.empty() ? 0.0 : rest_velocities[static_cast<std::size_t>(i)];
  }
  /// Gravity in the base frame [m/s^2]; (0, 0, -9.81) by default.
  const Vector3<Scalar>& gravity() const { return gravity_; }
  /// The drive terms that act (and are parameters); none by default.
  DriveTerms driveTerms() const { return drive_terms_; }

  // The structure and parameters, read-only (addBody and the setters write them).
  const std::vector<int>& parents() const { return parents_; }
  const std::vector<JointType>& joint_types() const { return joint_types_; }
  const std::vector<Pose<Scalar>>& joint_placements() const { return joint_placements_; }
  const std::vector<Pose<Scalar>>& body_placements() const { return body_placements_; }
  const std::vector<Vector3<Scalar>>& axes() const { return axes_; }  // unit, in the joint frame
  const std::vector<RigidInertia<Scalar>>& inertias() const { return inertias_; }  // link frames
  const std::vector<DriveParameters<Scalar>>& drives() const { return drives_; }

  // Derived by finalize() and refreshed by every setter. The algorithms work in joint frames:
  // joint frame i is body i's frame before body_placement_i, so that the motion subspace there is
  // the constant (axis, 0) or (0, axis) and, for a unit axis, a single entry.
  /// Joint frame i at q_i = 0 in the parent's joint frame: body_placement_p * joint_placement_i.
  const std::vector<Pose<Scalar>>& frame_placements() const { return frame_placements_; }
  /// Body i's inertia in joint frame i, and the same as 6x6 matrices (aba).
  const std::vector<RigidInertia<Scalar>>& frame_inertias() const { return frame_inertias_; }
  const std::vector<Matrix6<Scalar>>& frame_inertia_matrices() const {
    return frame_inertia_matrices_;
  }
  const std::vector<Vector6<Scalar>>& motion_subspaces() const { return motion_subspaces_; }
  const std::vector<AxisKind>& axis_kinds() const { return axis_kinds_; }
  /// k when S_i is the unit vector e_k (0..5), else -1.
  const std::vector<int>& subspace_index() const { return subspace_index_; }
  /// 0 when joint i's frame placement is the identity.
  const std::vector<char>& has_frame_placement() const { return has_frame_placement_; }
  /// For a revolute z joint whose frame placement rotates by a signed permutation (exact 0 and
  /// +-1 entries, as DH twists of 0 and +-90 degrees give): the index into kAxisPermutations of
  /// the permutation pi with rotation(a, pi(a)) = +-1, else -1; and det(Pi) Pi^T t, t the
  /// placement's translation. ABA's articulated-inertia transform then rotates about z and
  /// permutes (aba_detail::addTransformedInertiaPermuted).
  const std::vector<int>& placement_permutation() const { return placement_permutation_; }
  const std::vector<Vector3<Scalar>>& placement_shift() const { return placement_shift_; }

  int numJoints() const { return static_cast<int>(parents_.size()); }
  /// Whether finalize() has run since the last addBody.
  bool finalized() const { return static_cast<int>(motion_subspaces_.size()) == numJoints(); }

  /// Appends a body and its joint; returns its index. `parent` is -1 (base) or an existing index.
  /// Call finalize() after the last body. Throws InputError on an invalid parent.
  int addBody(int parent, std::string link_name, std::string joint_name, JointType type,
              const Pose<Scalar>& joint_placement, const Vector3<Scalar>& axis,
              const Pose<Scalar>& body_placement, const RigidInertia<Scalar>& inertia,
              const JointLimits& joint_limits = {}, const DriveParameters<Scalar>& drive = {});

  /// Validates the model (topological order, unit axes, finite numbers) and derives the cached
  /// fields. Call it after the last addBody (and again after changing gravity, to validate it).
  /// Throws InputError naming the body at fault.
  void finalize();

  ParameterLayout parameterLayout() const { return {numJoints(), drive_terms_}; }

  /// Sets gravity. Throws InputError unless every entry is finite and |g| <= kMaxGravity.
  void setGravity(const Vector3<Scalar>& g);
  /// Sets which drive terms act. Every joint keeps its drive values (a disabled term's value is
  /// kept and does not act); the parameter layout, and so a Data's regressor width, change with
  /// it: build Data after this call (checkData refuses an older one).
  void setDriveTerms(DriveTerms terms) { drive_terms_ = terms; }

  /// The standard parameter vector theta (order: parameters.hpp), size parameterLayout().size().
  VectorX<Scalar> standardParameters() const;
  /// Sets every inertial (and drive, when enabled) parameter from theta and updates the derived
  /// joint-frame inertias. Throws InputError on a size mismatch.
  void setStandardParameters(const VectorX<Scalar>& theta);
  /// Sets link i's inertia (in its link frame) and, once finalized, its joint-frame caches.
  /// Throws InputError on an index out of range.
  void setLinkInertia(int i, const RigidInertia<Scalar>& inertia);
  /// Sets every link's inertia (numJoints() entries) and the joint-frame caches. Throws InputError
  /// on a size mismatch.
  void setLinkInertias(const std::vector<RigidInertia<Scalar>>& inertias);
  /// Sets joint i's drive parameters. Throws InputError on an index out of range.
  void setDrive(int i, const DriveParameters<Scalar>& drive);
  /// Sets joint i's joint placement (in the parent link frame) or body i's placement (link frame
  /// in joint frame), and, once finalized, re-derives every cache (finalize(): its InputErrors
  /// too). Throws InputError on an index out of range.
  void setJointPlacement(int i, const Pose<Scalar>& placement);
  void setBodyPlacement(int i, const Pose<Scalar>& placement);
  /// Whether finalize() marks signed-permutation placements for ABA's permuted transform path
  /// (default true); false makes every joint take the general path, as a robot whose placements
  /// are not exact permutations does (benchmarks and tests compare the two). Re-derives the caches
  /// once finalized.
  void setPermutedPlacements(bool enabled);

  /// Whether every derived cache equals what finalize() derives from the current structure and
  /// parameters (Pinocchio's model.check()): true for any model built through the public API.
  /// Exactly for double; to 1e-12 relative for another scalar (a cast model's caches were computed
  /// in double).
  /// Debug builds assert it when a Data is built.
  bool cachesAreCurrent() const;

  /// The same model with every number converted to NewScalar (e.g. ceres::Jet).
  template <typename NewScalar>
  ModelTpl<NewScalar> cast() const;

 private:
  template <typename>
  friend class ModelTpl;

  /// Throws InputError unless 0 <= i < numJoints() ("link index 7 is out of range: ...").
  void checkIndex(int i, const char* what) const;
  /// Recomputes frame_inertias and frame_inertia_matrices from inertias.
  void updateFrameInertias() {
    frame_inertias_.resize(inertias_.size());
    frame_inertia_matrices_.resize(inertias_.size());
    for (std::size_t i = 0; i < inertias_.size(); ++i) updateFrameInertia(static_cast<int>(i));
  }
  void updateFrameInertia(int i) {
    frame_inertias_[i] = inertias_[i].transformedBy(body_placements_[i]);
    frame_inertia_matrices_[i] = frame_inertias_[i].matrix();
  }

  Vector3<Scalar> gravity_ = Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(-9.81));
  DriveTerms drive_terms_;
  std::vector<int> parents_;
  std::vector<JointType> joint_types_;
  std::vector<Pose<Scalar>> joint_placements_;
  std::vector<Pose<Scalar>> body_placements_;
  std::vector<Vector3<Scalar>> axes_;
  std::vector<RigidInertia<Scalar>> inertias_;
  std::vector<DriveParameters<Scalar>> drives_;
  std::vector<Pose<Scalar>> frame_placements_;
  std::vector<RigidInertia<Scalar>> frame_inertias_;
  std::vector<Matrix6<Scalar>> frame_inertia_matrices_;
  std::vector<Vector6<Scalar>> motion_subspaces_;
  std::vector<AxisKind> axis_kinds_;
  std::vector<int> subspace_index_;
  std::vector<char> has_frame_placement_;
  std::vector<int> placement_permutation_;
  std::vector<Vector3<Scalar>> placement_shift_;
  bool permuted_placements_ = true;
};

using Model = ModelTpl<double>;

/// The sum of the links' masses [kg].
template <typename Scalar>
Scalar totalMass(const ModelTpl<Scalar>& model) {
  Scalar total(0);
  for (const RigidInertia<Scalar>& inertia : model.inertias()) total += inertia.mass;
  return total;
}

/// Writes revolute (or continuous) joint i's jointTransform into `out` from s = sin(q_i),
/// c = cos(q_i). In place, entry by entry: a Pose built in a temporary and copied would be
/// written as scalars and reloaded as packed pairs, which stalls store-to-load forwarding.
template <typename Scalar>
DYNID_INLINE void setRevoluteTransform(const ModelTpl<Scalar>& model, int i, const Scalar& s,
                                       const Scalar& c, Pose<Scalar>& out) {
  const Pose<Scalar>& placement = model.frame_placements()[i];
  if (model.axis_kinds()[i] == AxisKind::kZ) {
    // P Rz(q): only the first two columns of P mix.
    if (!model.has_frame_placement()[i]) {
      out.rotation << c, -s, Scalar(0), s, c, Scalar(0), Scalar(0), Scalar(0), Scalar(1);
      out.translation.setZero();
      return;
    }
    out.rotation.col(0) = c * placement.rotation.col(0) + s * placement.rotation.col(1);
    out.rotation.col(1) = c * placement.rotation.col(1) - s * placement.rotation.col(0);
    out.rotation.col(2) = placement.rotation.col(2);
    out.translation = placement.translation;
    return;
  }
  Matrix3<Scalar> r = Matrix3<Scalar>::Identity();
  switch (model.axis_kinds()[i]) {
    case AxisKind::kX:
      r(1, 1) = c, r(1, 2) = -s, r(2, 1) = s, r(2, 2) = c;
      break;
    case AxisKind::kY:
      r(0, 0) = c, r(0, 2) = s, r(2, 0) = -s, r(2, 2) = c;
      break;
    default: {
      const Matrix3<Scalar> k = skew(model.axes()[i]);
      r.noalias() += s * k + (Scalar(1) - c) * (k * k);
      break;
    }
  }
  out.rotation.noalias() = placement.rotation * r;
  out.translation = placement.translation;
}

/// Writes joint i's jointTransform at q_i into `out` (see setRevoluteTransform).
template <typename Scalar>
DYNID_INLINE void setJointTransform(const ModelTpl<Scalar>& model, int i, const Scalar& qi,
                                    Pose<Scalar>& out) {
  using std::cos;
  using std::sin;
  if (model.joint_types()[i] == JointType::kPrismatic) {
    const Pose<Scalar>& placement = model.frame_placements()[i];
    out.rotation = placement.rotation;
    out.translation = placement.translation + placement.rotation * (model.axes()[i] * qi);
    return;
  }
  setRevoluteTransform(model, i, Scalar(sin(qi)), Scalar(cos(qi)), out);
}

/// Joint frame i placed in its parent's joint frame: frame_placement_i * J(q_i), where J rotates
/// about (revolute, continuous) or translates along (prismatic) the joint axis.
template <typename Scalar>
DYNID_INLINE Pose<Scalar> jointTransform(const ModelTpl<Scalar>& model, int i, const Scalar& qi) {
  Pose<Scalar> out;
  setJointTransform(model, i, qi, out);
  return out;
}

/// jointTransform of revolute (or continuous) joint i from s = sin(q_i), c = cos(q_i).
template <typename Scalar>
DYNID_INLINE Pose<Scalar> revoluteTransform(const ModelTpl<Scalar>& model, int i, const Scalar& s,
                                            const Scalar& c) {
  Pose<Scalar> out;
  setRevoluteTransform(model, i, s, c, out);
  return out;
}

/// S_i x: the joint's motion at rate x, in joint frame i.
template <typename Scalar>
DYNID_INLINE Vector6<Scalar> jointMotionAt(const ModelTpl<Scalar>& model, int i, const Scalar& x) {
  const int k = model.subspace_index()[i];
  if (k < 0) return model.motion_subspaces()[i] * x;
  Vector6<Scalar> out = Vector6<Scalar>::Zero();
  out[k] = x;
  return out;
}

/// m += S_i x.
template <typename Scalar>
DYNID_INLINE void addJointMotion(const ModelTpl<Scalar>& model, int i, const Scalar& x,
                                 Vector6<Scalar>& m) {
  const int k = model.subspace_index()[i];
  if (k >= 0)
    m[k] += x;
  else
    m += model.motion_subspaces()[i] * x;
}

/// S_i^T f: the generalized force of a spatial force f on joint i.
template <typename Scalar>
DYNID_INLINE Scalar projectOnJoint(const ModelTpl<Scalar>& model, int i, const Vector6<Scalar>& f) {
  const int k = model.subspace_index()[i];
  return k >= 0 ? f[k] : model.motion_subspaces()[i].dot(f);
}

/// v x (S_i x), the velocity-product acceleration of joint i.
template <typename Scalar>
DYNID_INLINE Vector6<Scalar> crossJointMotion(const ModelTpl<Scalar>& model, int i,
                                              const Vector6<Scalar>& v, const Scalar& x) {
  if (model.subspace_index()[i] == 2) {
    // S = (e_z, 0): (w x e_z, v x e_z) x.
    Vector6<Scalar> out;
    out << v[1] * x, -v[0] * x, Scalar(0), v[4] * x, -v[3] * x, Scalar(0);
    return out;
  }
  return crossMotion(v, jointMotionAt(model, i, x));
}

// ---- template implementation ----

template <typename Scalar>
template <typename NewScalar>
ModelTpl<NewScalar> ModelTpl<Scalar>::cast() const {
  ModelTpl<NewScalar> out;
  out.name = name;
  out.link_names = link_names;
  out.joint_names = joint_names;
  out.parents_ = parents_;
  out.joint_types_ = joint_types_;
  out.limits = limits;
  out.rest_velocities = rest_velocities;
  out.drive_terms_ = drive_terms_;
  out.axis_kinds_ = axis_kinds_;
  out.subspace_index_ = subspace_index_;
  out.has_frame_placement_ = has_frame_placement_;
  out.placement_permutation_ = placement_permutation_;
  out.permuted_placements_ = permuted_placements_;
  out.gravity_ = gravity_.template cast<NewScalar>();
  const int n = numJoints();
  out.joint_placements_.resize(n);
  out.body_placements_.resize(n);
  out.axes_.resize(n);
  out.inertias_.resize(n);
  out.drives_.resize(n);
  out.motion_subspaces_.resize(n);
  out.frame_placements_.resize(n);
  out.frame_inertias_.resize(n);
  out.frame_inertia_matrices_.resize(n);
  out.placement_shift_.resize(n);
  for (int i = 0; i < n; ++i) {
    out.joint_placements_[i] = joint_placements_[i].template cast<NewScalar>();
    out.body_placements_[i] = body_placements_[i].template cast<NewScalar>();
    out.axes_[i] = axes_[i].template cast<NewScalar>();
    out.inertias_[i] = inertias_[i].template cast<NewScalar>();
    for (int k = 0; k < kDriveTermCount; ++k)
      out.drives_[i].term(k) = NewScalar(drives_[i].term(k));
    out.motion_subspaces_[i] = motion_subspaces_[i].template cast<NewScalar>();
    out.frame_placements_[i] = frame_placements_[i].template cast<NewScalar>();
    out.frame_inertias_[i] = frame_inertias_[i].template cast<NewScalar>();
    out.frame_inertia_matrices_[i] = frame_inertia_matrices_[i].template cast<NewScalar>();
    out.placement_shift_[i] = placement_shift_[i].template cast<NewScalar>();
  }
  return out;
}

extern template class ModelTpl<double>;

}  // namespace dynid
