#pragma once

#include "core/aba.hpp"
#include "core/checks.hpp"
#include "core/friction.hpp"

namespace dynid {

namespace aba_detail {
/// parent += pXi* child iXp for a symmetric 6x6 articulated inertia given in the child frame,
/// with pXi* = [[R, [p]x R], [0, R]]: rotate the three 3x3 blocks, then shift by p.
template <typename Scalar>
void addTransformedInertia(const Pose<Scalar>& X, const Matrix6<Scalar>& child,
                           Matrix6<Scalar>& parent) {
  const Matrix3<Scalar>& R = X.rotation;
  const Matrix3<Scalar> A = R * child.template topLeftCorner<3, 3>() * R.transpose();
  const Matrix3<Scalar> B = R * child.template topRightCorner<3, 3>() * R.transpose();
  const Matrix3<Scalar> C = R * child.template bottomRightCorner<3, 3>() * R.transpose();
  const Matrix3<Scalar> P = skew(X.translation);
  // [[1, P], [0, 1]] [[A, B], [B^T, C]] [[1, 0], [P^T, 1]] with P^T = -P.
  const Matrix3<Scalar> B2 = B + P * C;
  parent.template topLeftCorner<3, 3>() += A + P * B.transpose() - B2 * P;
  parent.template topRightCorner<3, 3>() += B2;
  parent.template bottomLeftCorner<3, 3>() += B2.transpose();
  parent.template bottomRightCorner<3, 3>() += C;
}

}  // namespace aba_detail

template <typename Scalar>
const VectorX<Scalar>& aba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                           const ConstVectorRef<Scalar>& tau) {
  checkData(model, data);
  checkSize(model, q, "q");
  checkSize(model, dq, "dq");
  checkSize(model, tau, "tau");
  const int n = model.numJoints();

  // Pass 1: velocities, velocity-product accelerations c_i = v_i x S dq, and the rigid-body
  // inertias and bias forces pA_i = v_i x* I v_i.
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i] = jointTransform(model, i, q[i]);
    const int p = model.parents[i];
    Vector6<Scalar>& v = data.v[i];
    if (p < 0) {
      v = jointMotionAt(model, i, dq[i]);
      data.c[i].setZero();
    } else {
      v = X.actInvMotion(data.v[p]);
      addJointMotion(model, i, dq[i], v);
      data.c[i] = crossJointMotion(model, i, v, dq[i]);
    }
    const RigidInertia<Scalar>& I = model.frame_inertias[i];
    data.articulated_inertia[i] = I.matrix();
    data.bias_force[i] = crossForce(v, I.apply(v));
    data.u[i] = tau[i] - jointFriction(model, i, dq[i]);
  }
  // Pass 2 (leaves to root): U = IA S, D = S^T U + Ia, u = tau - S^T pA; the parent receives
  // IA - U U^T / D and pA + Ia c + U u / D.
  for (int i = n - 1; i >= 0; --i) {
    const Matrix6<Scalar>& IA = data.articulated_inertia[i];
    const int k = model.subspace_index[i];
    if (k >= 0)
      data.U[i] = IA.col(k);
    else
      data.U[i].noalias() = IA * model.motion_subspaces[i];
    data.D[i] = projectOnJoint(model, i, data.U[i]);
    if (model.drives_enabled) data.D[i] += model.drives[i].rotor_inertia;
    data.u[i] -= projectOnJoint(model, i, data.bias_force[i]);
    const int p = model.parents[i];
    if (p < 0) continue;
    const Scalar inv_d = Scalar(1) / data.D[i];
    const Matrix6<Scalar> Ia = IA - (inv_d * data.U[i]) * data.U[i].transpose();
    const Vector6<Scalar> pa =
        data.bias_force[i] + Ia * data.c[i] + data.U[i] * (data.u[i] * inv_d);
    aba_detail::addTransformedInertia(data.liMi[i], Ia, data.articulated_inertia[p]);
    data.bias_force[p] += data.liMi[i].actForce(pa);
  }
  // Pass 3 (root to leaves): a' = iXp a_p + c, ddq = (u - U^T a') / D, a = a' + S ddq.
  Vector6<Scalar> base_acceleration;
  base_acceleration << Scalar(0), Scalar(0), Scalar(0), -model.gravity;
  for (int i = 0; i < n; ++i) {
    const int p = model.parents[i];
    data.a[i] = data.liMi[i].actInvMotion(p < 0 ? base_acceleration : data.a[p]) + data.c[i];
    data.ddq[i] = (data.u[i] - data.U[i].dot(data.a[i])) / data.D[i];
    addJointMotion(model, i, data.ddq[i], data.a[i]);
  }
  return data.ddq;
}

}  // namespace dynid
