#pragma once

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/rnea.hpp"

namespace dynid {

template <typename Scalar>
const VectorX<Scalar>& rnea(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                            const ConstVectorRef<Scalar>& ddq) {
  checkData(model, data);
  checkSize(model, q, "q");
  checkSize(model, dq, "dq");
  checkSize(model, ddq, "ddq");
  const int n = model.numJoints();
  // The base accelerates at -g, which adds gravity to every body.
  Vector6<Scalar> base_acceleration;
  base_acceleration << Scalar(0), Scalar(0), Scalar(0), -model.gravity;

  // Forward pass: v_i = iXp v_p + S dq,  a_i = iXp a_p + S ddq + v_i x S dq,
  // f_i = I a_i + v_i x* I v_i.
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i] = jointTransform(model, i, q[i]);
    const Vector6<Scalar>& S = model.motion_subspaces[i];
    const int p = model.parents[i];
    const Vector6<Scalar> vJ = S * dq[i];
    if (p < 0) {
      data.v[i] = vJ;
      data.a[i] = X.actInvMotion(base_acceleration) + S * ddq[i];
    } else {
      data.v[i] = X.actInvMotion(data.v[p]) + vJ;
      data.a[i] = X.actInvMotion(data.a[p]) + S * ddq[i] + crossMotion(data.v[i], vJ);
    }
    const RigidInertia<Scalar>& I = model.inertias[i];
    data.f[i] = I.apply(data.a[i]) + crossForce(data.v[i], I.apply(data.v[i]));
  }
  // Backward pass: tau_i = S^T f_i (+ drives), f_p += pXi* f_i.
  for (int i = n - 1; i >= 0; --i) {
    data.tau[i] = model.motion_subspaces[i].dot(data.f[i]);
    if (model.drives_enabled)
      data.tau[i] += model.drives[i].rotor_inertia * ddq[i] + jointFriction(model, i, dq[i]);
    const int p = model.parents[i];
    if (p >= 0) data.f[p] += data.liMi[i].actForce(data.f[i]);
  }
  return data.tau;
}

}  // namespace dynid
