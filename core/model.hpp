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
  double velocity = std::numeric_limits<double>::infinity();  // [rad/s or m/s]
  double effort = std::numeric_limits<double>::infinity();    // [N m or N]
};

/// Joint-side drive parameters (see parameters.hpp for the friction law).
template <typename Scalar>
struct DriveParameters {
  Scalar rotor_inertia = Scalar(0);  // Ia [kg m^2]
  Scalar viscous = Scalar(0);        // Fv [N m s/rad]
  Scalar coulomb = Scalar(0);        // Fc [N m]
  Scalar offset = Scalar(0);         // Fo [N m]
};

/// How a joint's axis is stored, so the hot path can skip Rodrigues' formula for unit axes.
enum class AxisKind { kX, kY, kZ, kGeneral };

/// The six permutations of (0, 1, 2) in lexicographic order, and their determinants.
inline constexpr int kAxisPermutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                                {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
inline constexpr int kAxisPermutationSigns[6] = {1, -1, -1, 1, 1, -1};

template <typename Scalar>
struct ModelTpl {
  std::string name;
  std::vector<std::string> link_names;
  std::vector<std::string> joint_names;
  std::vector<int> parents;
  std::vector<JointType> joint_types;
  std::vector<Pose<Scalar>> joint_placements;
  std::vector<Pose<Scalar>> body_placements;
  std::vector<Vector3<Scalar>> axes;  // unit vectors in the joint frame
  std::vector<RigidInertia<Scalar>> inertias;
  std::vector<DriveParameters<Scalar>> drives;
  std::vector<JointLimits> limits;
  Vector3<Scalar> gravity = Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(-9.81));  // [m/s^2]
  bool drives_enabled = false;   // rotor inertia and friction act (and are parameters)
  bool offsets_enabled = false;  // Fo acts (only with drives)

  // Derived by finalize() (and setStandardParameters); do not set by hand. The algorithms work in
  // joint frames: joint frame i is body i's frame before body_placement_i, so that the motion
  // subspace there is the constant (axis, 0) or (0, axis) and, for a unit axis, a single entry.
  std::vector<Pose<Scalar>> frame_placements;  // joint frame i at q_i = 0 in the parent's joint
                                               // frame: body_placement_p * joint_placement_i
  std::vector<RigidInertia<Scalar>> frame_inertias;     // body i's inertia in joint frame i
  std::vector<Matrix6<Scalar>> frame_inertia_matrices;  // the same as 6x6 matrices (aba)
  std::vector<Vector6<Scalar>> motion_subspaces;        // S_i in joint frame i
  std::vector<AxisKind> axis_kinds;
  std::vector<int> subspace_index;        // k when S_i is the unit vector e_k (0..5), else -1
  std::vector<char> has_frame_placement;  // 0 when identity
  // For a revolute z joint whose frame placement rotates by a signed permutation (exact 0 and +-1
  // entries, as DH twists of 0 and +-90 degrees give): the index into kAxisPermutations of the
  // permutation pi with rotation(a, pi(a)) = +-1, else -1; and det(Pi) Pi^T t, t the placement's
  // translation. ABA's articulated-inertia transform then rotates about z and permutes
  // (aba_detail::addTransformedInertiaPermuted).
  std::vector<int> placement_permutation;
  std::vector<Vector3<Scalar>> placement_shift;

  int numJoints() const { return static_cast<int>(parents.size()); }

  /// Appends a body and its joint; returns its index. `parent` is -1 (base) or an existing index.
  /// Call finalize() after the last body. Throws InputError on an invalid parent.
  int addBody(int parent, std::string link_name, std::string joint_name, JointType type,
              const Pose<Scalar>& joint_placement, const Vector3<Scalar>& axis,
              const Pose<Scalar>& body_placement, const RigidInertia<Scalar>& inertia,
              const JointLimits& joint_limits = {}, const DriveParameters<Scalar>& drive = {});

  /// Validates the model (topological order, unit axes, finite numbers) and derives the cached
  /// fields. Call it again after changing any field. Throws InputError naming the body at fault.
  void finalize();

  ParameterLayout parameterLayout() const { return {numJoints(), drives_enabled, offsets_enabled}; }

  /// The standard parameter vector theta (order: parameters.hpp), size parameterLayout().size().
  VectorX<Scalar> standardParameters() const;
  /// Sets every inertial (and drive, when enabled) parameter from theta and updates the derived
  /// joint-frame inertias. Throws InputError on a size mismatch.
  void setStandardParameters(const VectorX<Scalar>& theta);

  /// Recomputes frame_inertias and frame_inertia_matrices from inertias (after changing inertias
  /// by hand).
  void updateFrameInertias() {
    frame_inertias.resize(inertias.size());
    frame_inertia_matrices.resize(inertias.size());
    for (std::size_t i = 0; i < inertias.size(); ++i) {
      frame_inertias[i] = inertias[i].transformedBy(body_placements[i]);
      frame_inertia_matrices[i] = frame_inertias[i].matrix();
    }
  }

  /// The same model with every number converted to NewScalar (e.g. ceres::Jet).
  template <typename NewScalar>
  ModelTpl<NewScalar> cast() const;
};

using Model = ModelTpl<double>;

/// Writes revolute (or continuous) joint i's jointTransform into `out` from s = sin(q_i),
/// c = cos(q_i). In place, entry by entry: a Pose built in a temporary and copied would be
/// written as scalars and reloaded as packed pairs, which stalls store-to-load forwarding.
template <typename Scalar>
DYNID_INLINE void setRevoluteTransform(const ModelTpl<Scalar>& model, int i, const Scalar& s,
                                       const Scalar& c, Pose<Scalar>& out) {
  const Pose<Scalar>& placement = model.frame_placements[i];
  if (model.axis_kinds[i] == AxisKind::kZ) {
    // P Rz(q): only the first two columns of P mix.
    if (!model.has_frame_placement[i]) {
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
  switch (model.axis_kinds[i]) {
    case AxisKind::kX:
      r(1, 1) = c, r(1, 2) = -s, r(2, 1) = s, r(2, 2) = c;
      break;
    case AxisKind::kY:
      r(0, 0) = c, r(0, 2) = s, r(2, 0) = -s, r(2, 2) = c;
      break;
    default: {
      const Matrix3<Scalar> k = skew(model.axes[i]);
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
  if (model.joint_types[i] == JointType::kPrismatic) {
    const Pose<Scalar>& placement = model.frame_placements[i];
    out.rotation = placement.rotation;
    out.translation = placement.translation + placement.rotation * (model.axes[i] * qi);
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
  const int k = model.subspace_index[i];
  if (k < 0) return model.motion_subspaces[i] * x;
  Vector6<Scalar> out = Vector6<Scalar>::Zero();
  out[k] = x;
  return out;
}

/// m += S_i x.
template <typename Scalar>
DYNID_INLINE void addJointMotion(const ModelTpl<Scalar>& model, int i, const Scalar& x,
                                 Vector6<Scalar>& m) {
  const int k = model.subspace_index[i];
  if (k >= 0)
    m[k] += x;
  else
    m += model.motion_subspaces[i] * x;
}

/// S_i^T f: the generalized force of a spatial force f on joint i.
template <typename Scalar>
DYNID_INLINE Scalar projectOnJoint(const ModelTpl<Scalar>& model, int i, const Vector6<Scalar>& f) {
  const int k = model.subspace_index[i];
  return k >= 0 ? f[k] : model.motion_subspaces[i].dot(f);
}

/// v x (S_i x), the velocity-product acceleration of joint i.
template <typename Scalar>
DYNID_INLINE Vector6<Scalar> crossJointMotion(const ModelTpl<Scalar>& model, int i,
                                              const Vector6<Scalar>& v, const Scalar& x) {
  if (model.subspace_index[i] == 2) {
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
  out.parents = parents;
  out.joint_types = joint_types;
  out.limits = limits;
  out.drives_enabled = drives_enabled;
  out.offsets_enabled = offsets_enabled;
  out.axis_kinds = axis_kinds;
  out.subspace_index = subspace_index;
  out.has_frame_placement = has_frame_placement;
  out.placement_permutation = placement_permutation;
  out.gravity = gravity.template cast<NewScalar>();
  const int n = numJoints();
  out.joint_placements.resize(n);
  out.body_placements.resize(n);
  out.axes.resize(n);
  out.inertias.resize(n);
  out.drives.resize(n);
  out.motion_subspaces.resize(n);
  out.frame_placements.resize(n);
  out.frame_inertias.resize(n);
  out.frame_inertia_matrices.resize(n);
  out.placement_shift.resize(n);
  for (int i = 0; i < n; ++i) {
    out.joint_placements[i] = joint_placements[i].template cast<NewScalar>();
    out.body_placements[i] = body_placements[i].template cast<NewScalar>();
    out.axes[i] = axes[i].template cast<NewScalar>();
    out.inertias[i] = inertias[i].template cast<NewScalar>();
    out.drives[i].rotor_inertia = NewScalar(drives[i].rotor_inertia);
    out.drives[i].viscous = NewScalar(drives[i].viscous);
    out.drives[i].coulomb = NewScalar(drives[i].coulomb);
    out.drives[i].offset = NewScalar(drives[i].offset);
    out.motion_subspaces[i] = motion_subspaces[i].template cast<NewScalar>();
    out.frame_placements[i] = frame_placements[i].template cast<NewScalar>();
    out.frame_inertias[i] = frame_inertias[i].template cast<NewScalar>();
    out.frame_inertia_matrices[i] = frame_inertia_matrices[i].template cast<NewScalar>();
    out.placement_shift[i] = placement_shift[i].template cast<NewScalar>();
  }
  return out;
}

extern template struct ModelTpl<double>;

}  // namespace dynid
