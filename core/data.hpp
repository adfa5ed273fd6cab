// The workspace of every algorithm: built once from a Model (`Data data(model)`), it holds every
// result and scratch buffer, so the algorithms allocate nothing once it exists. One Data per
// thread; the Model is shared read-only.
#pragma once

#include <cassert>
#include <vector>

#include "core/model.hpp"

namespace dynid {

template <int W, int Isa>
struct Lanes;
template <typename Scalar>
inline constexpr bool kIsLanes = false;
template <int W, int Isa>
inline constexpr bool kIsLanes<Lanes<W, Isa>> = true;

template <typename Scalar>
struct DataTpl {
  explicit DataTpl(const ModelTpl<Scalar>& model);

  // Kinematics. The recursive algorithms work in joint frames (model.hpp): liMi places joint frame
  // i in its parent's joint frame (every dynamics algorithm sets it); forwardKinematics also sets
  // oMj (joint frame i in the base frame) and oMi (link frame i, the frame of the user's
  // parameters, in the base frame).
  std::vector<Pose<Scalar>> liMi;
  std::vector<Pose<Scalar>> oMj;
  std::vector<Pose<Scalar>> oMi;

  // Recursive algorithms: body velocity, acceleration (including -gravity at the base) and the
  // force each body transmits to its parent, all in joint frame i.
  std::vector<Vector6<Scalar>> v, a, f;

  VectorX<Scalar> tau;  // rnea output [N m]
  VectorX<Scalar> ddq;  // aba output [rad/s^2]
  MatrixX<Scalar> M;    // crba output, the joint-space mass matrix [kg m^2]
  MatrixX<Scalar> Y;    // jointTorqueRegressor output, n x parameterLayout().size()
  /// jointTorqueRegressor: joint j's motion axis S_j expressed in joint frame i (j an ancestor of
  /// i, or i itself), at j n + i.
  std::vector<Vector6<Scalar>> joint_axes;

  // CRBA: composite inertia of each subtree, in the subtree root's frame; joint i's column force
  // Ic_i S_i on its way to the root, and the joint frame it is in (-1 once used up).
  std::vector<RigidInertia<Scalar>> composite;
  std::vector<Vector6<Scalar>> column_force;
  std::vector<int> column_frame;

  // ABA: articulated inertias and bias forces, U = IA S, D = S^T IA S (+ Ia), u, bias accel c.
  std::vector<Matrix6<Scalar>> articulated_inertia;
  /// Whether a child has written articulated_inertia[i] in this call (else it is the joint frame
  /// rigid-body inertia, read from the model).
  std::vector<char> articulated_written;
  std::vector<Vector6<Scalar>> bias_force, U, c;
  std::vector<Vector6<Scalar>> U_parent;  // pXi* U, U in the parent's frame
  VectorX<Scalar> D, D_inv, u, u_minus_Uc;

  // Integrators: stage state and accumulated increments; sin q and cos q of the step's start
  // (revolute joints), from which RK4 forms its later stages' joint transforms.
  VectorX<Scalar> q_stage, dq_stage, q_increment, dq_increment, sin_q, cos_q;
};

using Data = DataTpl<double>;

template <typename Scalar>
DataTpl<Scalar>::DataTpl(const ModelTpl<Scalar>& model) {
  // (Lanes are never compared as finalize compares: a lane model is cast from a checked one.)
  if constexpr (!kIsLanes<Scalar>)
    assert(model.cachesAreCurrent() && "the model's derived caches are stale");
  const int n = model.numJoints();
  liMi.assign(n, Pose<Scalar>());
  oMj.assign(n, Pose<Scalar>());
  oMi.assign(n, Pose<Scalar>());
  v.assign(n, Vector6<Scalar>::Zero());
  a.assign(n, Vector6<Scalar>::Zero());
  f.assign(n, Vector6<Scalar>::Zero());
  tau = VectorX<Scalar>::Zero(n);
  ddq = VectorX<Scalar>::Zero(n);
  M = MatrixX<Scalar>::Zero(n, n);
  Y = MatrixX<Scalar>::Zero(n, model.parameterLayout().size());
  joint_axes.assign(static_cast<std::size_t>(n) * n, Vector6<Scalar>::Zero());
  composite.assign(n, RigidInertia<Scalar>());
  column_force.assign(n, Vector6<Scalar>::Zero());
  column_frame.assign(n, -1);
  articulated_inertia.assign(n, Matrix6<Scalar>::Zero());
  articulated_written.assign(n, 0);
  bias_force.assign(n, Vector6<Scalar>::Zero());
  U.assign(n, Vector6<Scalar>::Zero());
  c.assign(n, Vector6<Scalar>::Zero());
  U_parent.assign(n, Vector6<Scalar>::Zero());
  u_minus_Uc = VectorX<Scalar>::Zero(n);
  D = VectorX<Scalar>::Zero(n);
  D_inv = VectorX<Scalar>::Zero(n);
  u = VectorX<Scalar>::Zero(n);
  q_stage = VectorX<Scalar>::Zero(n);
  dq_stage = VectorX<Scalar>::Zero(n);
  q_increment = VectorX<Scalar>::Zero(n);
  dq_increment = VectorX<Scalar>::Zero(n);
  sin_q = VectorX<Scalar>::Zero(n);
  cos_q = VectorX<Scalar>::Zero(n);
}

/// Input vectors of the compiled algorithms. Scalar is deduced from the model argument only, so
/// a VectorXd, a column of a matrix or a segment can be passed without a copy.
template <typename Scalar>
using ConstVectorRef = std::type_identity_t<Eigen::Ref<const VectorX<Scalar>>>;
template <typename Scalar>
using VectorRef = std::type_identity_t<Eigen::Ref<VectorX<Scalar>>>;

}  // namespace dynid
