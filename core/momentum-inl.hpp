#pragma once

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/momentum.hpp"

namespace dynid {

template <typename Scalar>
void momentumTerms(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                   const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                   VectorX<Scalar>& p, VectorX<Scalar>& beta) {
  checkState(model, data, q, dq, dq, "dq");
  const int n = model.numJoints();
  p.resize(n);
  beta.resize(n);
  for (int i = 0; i < n; ++i) setJointTransform(model, i, q[i], data.liMi[i]);
  // Forward: v_i = iXp v_p + S dq; a_g,i = iXp a_g,p (a_g,0 = -gravity); h_i = I v_i into f,
  // the gravity force I a_g,i into a.
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i];
    const int parent = model.parents()[i];
    Vector6<Scalar> gravity_acc;
    if (parent < 0) {
      data.v[i].setZero();
      gravity_acc.template head<3>().setZero();
      gravity_acc.template tail<3>() = X.rotation.transpose() * (-model.gravity());
    } else {
      data.v[i] = X.actInvMotion(data.v[parent]);
      gravity_acc = X.actInvMotion(data.a[parent]);
    }
    addJointMotion(model, i, dq[i], data.v[i]);
    const RigidInertia<Scalar>& I = model.frame_inertias()[i];
    data.f[i] = I.apply(data.v[i]);
    // a_g stays a pure linear acceleration along the chain; kept in a until the body's force
    // replaces it below (children read it first: parents precede children).
    data.a[i] = gravity_acc;
  }
  // The gravity forces, once every child has read its parent's acceleration.
  for (int i = n - 1; i >= 0; --i) data.a[i] = model.frame_inertias()[i].apply(data.a[i]);
  // Backward: p_k = S^T H_k, beta_k = S^T (G_k + v_k x* H_k) + friction; H, G into the parent.
  for (int i = n - 1; i >= 0; --i) {
    p[i] = projectOnJoint(model, i, data.f[i]);
    beta[i] =
        projectOnJoint(model, i, Vector6<Scalar>(data.a[i] + crossForce(data.v[i], data.f[i])));
    if (model.driveTerms().any()) {
      p[i] += driveInertia(model, i) * dq[i];
      beta[i] += jointFriction(model, i, dq[i]);
    }
    const int parent = model.parents()[i];
    if (parent < 0) continue;
    data.f[parent] += data.liMi[i].actForce(data.f[i]);
    data.a[parent] += data.liMi[i].actForce(data.a[i]);
  }
}

}  // namespace dynid
