#pragma once

#include "core/aba.hpp"
#include "core/checks.hpp"
#include "core/friction.hpp"

namespace dynid {

namespace aba_detail {
/// parent += pXi* Ia iXp, where Ia = IA - U (U / D)^T is the articulated inertia the child hands
/// on (formed block by block here, never stored), with pXi* = [[R, [p]x R], [0, R]]: rotate the
/// three 3x3 blocks, then shift by p.
template <typename Scalar>
void addTransformedInertia(const Pose<Scalar>& X, const Matrix6<Scalar>& IA,
                           const Vector6<Scalar>& U, const Vector6<Scalar>& U_over_D,
                           Matrix6<Scalar>& parent) {
  const Matrix3<Scalar>& R = X.rotation;
  const auto Ut = U.template head<3>(), Ub = U.template tail<3>();
  const auto Vt = U_over_D.template head<3>(), Vb = U_over_D.template tail<3>();
  Matrix3<Scalar> block, half;
  // A = R (IA_tl - Ut Vt^T) R^T, B = R (IA_tr - Ut Vb^T) R^T, C = R (IA_br - Ub Vb^T) R^T.
  block.noalias() = IA.template topLeftCorner<3, 3>() - Ut * Vt.transpose();
  half.noalias() = R * block;
  Matrix3<Scalar> A;
  A.noalias() = half * R.transpose();
  block.noalias() = IA.template topRightCorner<3, 3>() - Ut * Vb.transpose();
  half.noalias() = R * block;
  Matrix3<Scalar> B;
  B.noalias() = half * R.transpose();
  block.noalias() = IA.template bottomRightCorner<3, 3>() - Ub * Vb.transpose();
  half.noalias() = R * block;
  Matrix3<Scalar> C;
  C.noalias() = half * R.transpose();
  // [[1, P], [0, 1]] [[A, B], [B^T, C]] [[1, 0], [P^T, 1]] with P = [p]x, P^T = -P:
  // B2 = B + P C, A' = A + P B^T - B2 P, each product with P a set of cross products with p.
  const Vector3<Scalar>& p = X.translation;
  Matrix3<Scalar> B2;
  for (int j = 0; j < 3; ++j) B2.col(j) = B.col(j) + cross(p, C.col(j));
  for (int j = 0; j < 3; ++j) A.col(j) += cross(p, B.row(j).transpose());
  for (int r = 0; r < 3; ++r) A.row(r) += cross(p, B2.row(r).transpose()).transpose();
  parent.template topLeftCorner<3, 3>() += A;
  parent.template topRightCorner<3, 3>() += B2;
  parent.template bottomLeftCorner<3, 3>() += B2.transpose();
  parent.template bottomRightCorner<3, 3>() += C;
}

/// ABA's three passes with data.liMi already holding the joint transforms at q (the sizes checked
/// by the caller). Inlined into aba and into abaAtTransforms.
template <typename Scalar>
DYNID_INLINE const VectorX<Scalar>& abaPasses(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                              const ConstVectorRef<Scalar>& dq,
                                              const ConstVectorRef<Scalar>& tau);

/// aba with data.liMi already holding the joint transforms at q (RK4's later stages form them by
/// angle addition). Kept out of line: RK4 calls it four times, and four inlined copies of the
/// passes made the step 30 % slower (instruction cache).
template <typename Scalar>
DYNID_NOINLINE const VectorX<Scalar>& abaAtTransforms(const ModelTpl<Scalar>& model,
                                                      DataTpl<Scalar>& data,
                                                      const ConstVectorRef<Scalar>& dq,
                                                      const ConstVectorRef<Scalar>& tau) {
  return abaPasses(model, data, dq, tau);
}

}  // namespace aba_detail

template <typename Scalar>
const VectorX<Scalar>& aba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                           const ConstVectorRef<Scalar>& tau) {
  checkState(model, data, q, dq, tau, "tau");
  // The joint transforms first (see rnea): independent sin/cos calls overlap.
  for (int i = 0; i < model.numJoints(); ++i) data.liMi[i] = jointTransform(model, i, q[i]);
  return aba_detail::abaPasses(model, data, dq, tau);
}

template <typename Scalar>
DYNID_INLINE const VectorX<Scalar>& aba_detail::abaPasses(const ModelTpl<Scalar>& model,
                                                          DataTpl<Scalar>& data,
                                                          const ConstVectorRef<Scalar>& dq,
                                                          const ConstVectorRef<Scalar>& tau) {
  const int n = model.numJoints();
  // Pass 1: velocities, velocity-product accelerations c_i = v_i x S dq, and the rigid-body
  // inertias and bias forces pA_i = v_i x* I v_i.
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i];
    const int p = model.parents[i];
    Vector6<Scalar>& v = data.v[i];
    if (p < 0) {
      v = jointMotionAt(model, i, dq[i]);
      data.c[i].setZero();
    } else {
      // v = iXp v_p + S dq on 3-vector halves (see rnea).
      const Vector3<Scalar> wp = data.v[p].template head<3>(), vp = data.v[p].template tail<3>();
      v.template head<3>().noalias() = X.rotation.transpose() * wp;
      v.template tail<3>().noalias() = X.rotation.transpose() * (vp - cross(X.translation, wp));
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
    // pa = pA + Ia c + U u / D with Ia c = IA c - U (U . c) / D.
    Vector6<Scalar> pa = data.bias_force[i];
    pa.noalias() += IA * data.c[i];
    pa += data.U[i] * ((data.u[i] - data.U[i].dot(data.c[i])) * inv_d);
    const Vector6<Scalar> U_over_D = data.U[i] * inv_d;
    aba_detail::addTransformedInertia(data.liMi[i], IA, data.U[i], U_over_D,
                                      data.articulated_inertia[p]);
    data.bias_force[p] += data.liMi[i].actForce(pa);
  }
  // Pass 3 (root to leaves): a' = iXp a_p + c, ddq = (u - U^T a') / D, a = a' + S ddq, on
  // 3-vector halves (see rnea).
  for (int i = 0; i < n; ++i) {
    const int p = model.parents[i];
    const Pose<Scalar>& X = data.liMi[i];
    Vector3<Scalar> dw, dv;
    if (p < 0) {
      dw.setZero();
      dv.noalias() = X.rotation.transpose() * (-model.gravity);
    } else {
      const Vector3<Scalar> dwp = data.a[p].template head<3>(), dvp = data.a[p].template tail<3>();
      dw.noalias() = X.rotation.transpose() * dwp;
      dv.noalias() = X.rotation.transpose() * (dvp - cross(X.translation, dwp));
    }
    dw += data.c[i].template head<3>();
    dv += data.c[i].template tail<3>();
    const Scalar ua = data.U[i].template head<3>().dot(dw) + data.U[i].template tail<3>().dot(dv);
    data.ddq[i] = (data.u[i] - ua) / data.D[i];
    data.a[i].template head<3>() = dw;
    data.a[i].template tail<3>() = dv;
    addJointMotion(model, i, data.ddq[i], data.a[i]);
  }
  return data.ddq;
}

}  // namespace dynid
