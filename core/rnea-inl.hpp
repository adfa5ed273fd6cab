#pragma once

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/rnea.hpp"

namespace dynid {

template <typename Scalar>
const VectorX<Scalar>& rnea(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                            const ConstVectorRef<Scalar>& ddq) {
  checkState(model, data, q, dq, ddq, "ddq");
  const int n = model.numJoints();
  // The recursion works on the angular and linear 3-vector halves of each spatial vector
  // separately: mixing scalar stores and packed loads on 6-vectors stalls store forwarding.
  using V3 = Vector3<Scalar>;

  // Forward pass: v_i = iXp v_p + S dq,  a_i = iXp a_p + S ddq + v_i x S dq,
  // f_i = I a_i + v_i x* I v_i.  The base accelerates at -g, which adds gravity to every body.
  // The joint transforms first: their sin/cos calls are independent of each other and of the
  // recursion, so the processor overlaps them instead of waiting in the dependency chain.
  for (int i = 0; i < n; ++i) setJointTransform(model, i, q[i], data.liMi[i]);
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i];
    const int p = model.parents()[i];
    V3 w, v, dw, dv;
    if (p < 0) {
      w.setZero(), v.setZero(), dw.setZero();
      dv.noalias() = X.rotation.transpose() * (-model.gravity());
    } else {
      // iXp m = (R^T w, R^T (v - p x w))
      const V3 wp = data.v[p].template head<3>(), vp = data.v[p].template tail<3>();
      const V3 dwp = data.a[p].template head<3>(), dvp = data.a[p].template tail<3>();
      w.noalias() = X.rotation.transpose() * wp;
      v.noalias() = X.rotation.transpose() * (vp - cross(X.translation, wp));
      dw.noalias() = X.rotation.transpose() * dwp;
      dv.noalias() = X.rotation.transpose() * (dvp - cross(X.translation, dwp));
    }
    Vector6<Scalar> vel, acc;
    vel << w, v;
    addJointMotion(model, i, dq[i], vel);
    acc << dw, dv;
    if (p >= 0) {
      const Vector6<Scalar> c = crossJointMotion(model, i, vel, dq[i]);
      acc.template head<3>() += c.template head<3>();
      acc.template tail<3>() += c.template tail<3>();
    }
    addJointMotion(model, i, ddq[i], acc);
    data.v[i] = vel;
    data.a[i] = acc;
    // f = I a + v x* (I v), with I v = (I_o w + h x v, m v - h x w).
    const RigidInertia<Scalar>& I = model.frame_inertias()[i];
    const V3 wi = vel.template head<3>(), vi = vel.template tail<3>();
    const V3 ai = acc.template head<3>(), li = acc.template tail<3>();
    const V3 hw = I.inertia * wi + cross(I.first_moment, vi);
    const V3 hv = I.mass * vi - cross(I.first_moment, wi);
    const V3 n_i = I.inertia * ai + cross(I.first_moment, li) + cross(wi, hw) + cross(vi, hv);
    const V3 f_i = I.mass * li - cross(I.first_moment, ai) + cross(wi, hv);
    data.f[i].template head<3>() = n_i;
    data.f[i].template tail<3>() = f_i;
  }
  // Backward pass: tau_i = S^T f_i (+ drives), f_p += pXi* f_i = (R n + p x R f, R f).
  for (int i = n - 1; i >= 0; --i) {
    data.tau[i] = projectOnJoint(model, i, data.f[i]);
    if (model.driveTerms().any()) data.tau[i] += driveTorque(model, i, dq[i], ddq[i]);
    const int p = model.parents()[i];
    if (p < 0) continue;
    const Pose<Scalar>& X = data.liMi[i];
    const V3 rf = X.rotation * V3(data.f[i].template tail<3>());
    const V3 rn = X.rotation * V3(data.f[i].template head<3>()) + cross(X.translation, rf);
    data.f[p].template head<3>() += rn;
    data.f[p].template tail<3>() += rf;
  }
  return data.tau;
}

}  // namespace dynid
