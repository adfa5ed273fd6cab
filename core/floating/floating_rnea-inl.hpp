// Template bodies of floating_rnea.hpp; include only to instantiate a new Scalar.
#pragma once

#include "core/floating/floating_rnea.hpp"
#include "core/friction.hpp"

namespace dynid {

namespace floating_detail {
/// The parent's velocity and acceleration of limb body i: the base's when it hangs from it.
template <typename Scalar>
const Vector6<Scalar>& parentOf(const std::vector<Vector6<Scalar>>& limb,
                                const Vector6<Scalar>& base, int parent) {
  return parent < 0 ? base : limb[static_cast<std::size_t>(parent)];
}

/// The forward pass shared by inverse dynamics and the regressor: every body's twist and
/// acceleration (gravity as the base's -g) in its joint frame, the base's in the base frame.
template <typename Scalar>
void forwardPass(const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
                 const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
                 const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& ddq) {
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  data.base_v = base.twist;
  data.base_a = base.acceleration;
  data.base_a.template tail<3>() -= transposeTimes(base.rotation, model.gravity());
  const int n = limbs.numJoints();
  for (int i = 0; i < n; ++i) setJointTransform(limbs, i, q[i], ld.liMi[i]);
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = ld.liMi[i];
    const int p = limbs.parents()[i];
    Vector6<Scalar> vel = X.actInvMotion(parentOf(ld.v, data.base_v, p));
    addJointMotion(limbs, i, dq[i], vel);
    Vector6<Scalar> acc = X.actInvMotion(parentOf(ld.a, data.base_a, p));
    acc += crossJointMotion(limbs, i, vel, dq[i]);
    addJointMotion(limbs, i, ddq[i], acc);
    ld.v[i] = vel;
    ld.a[i] = acc;
  }
}
}  // namespace floating_detail

template <typename Scalar>
const VectorX<Scalar>& floatingRnea(const FloatingModelTpl<Scalar>& model,
                                    FloatingDataTpl<Scalar>& data,
                                    const BaseMotionTpl<Scalar>& base,
                                    const ConstVectorRef<Scalar>& q,
                                    const ConstVectorRef<Scalar>& dq,
                                    const ConstVectorRef<Scalar>& ddq) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkState(limbs, ld, q, dq, ddq, "ddq");
  floating_detail::forwardPass(model, data, base, q, dq, ddq);
  // Each body's force f = I a + v x* (I v); the base body's likewise.
  const int n = limbs.numJoints();
  for (int i = 0; i < n; ++i) {
    const RigidInertia<Scalar>& I = limbs.frame_inertias()[i];
    ld.f[i] = I.apply(ld.a[i]) + crossForce(ld.v[i], I.apply(ld.v[i]));
  }
  const RigidInertia<Scalar>& IB = model.baseInertia();
  data.base_f = IB.apply(data.base_a) + crossForce(data.base_v, IB.apply(data.base_v));
  // Backward pass: tau_i = S_i^T f_i (+ drives); each force carried to its parent, the roots'
  // to the base body, whose total is the wrench the motion needs.
  for (int i = n - 1; i >= 0; --i) {
    Scalar tau_i = projectOnJoint(limbs, i, ld.f[i]);
    if (limbs.driveTerms().any()) tau_i += driveTorque(limbs, i, dq[i], ddq[i]);
    data.tau[6 + i] = tau_i;
    const int p = limbs.parents()[i];
    (p < 0 ? data.base_f : ld.f[p]) += ld.liMi[i].actForce(ld.f[i]);
  }
  data.tau.template head<6>() = data.base_f;
  return data.tau;
}

template <typename Scalar>
const MatrixX<Scalar>& floatingCrba(const FloatingModelTpl<Scalar>& model,
                                    FloatingDataTpl<Scalar>& data,
                                    const ConstVectorRef<Scalar>& q) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkSize(limbs, q, "q");
  const int n = limbs.numJoints();
  for (int i = 0; i < n; ++i) setJointTransform(limbs, i, q[i], ld.liMi[i]);
  // Composite inertias, leaves first, each in its joint frame; the roots' into the base's.
  for (int i = 0; i < n; ++i) ld.composite[i] = limbs.frame_inertias()[i];
  data.base_composite = model.baseInertia();
  for (int i = n - 1; i >= 0; --i) {
    const int p = limbs.parents()[i];
    (p < 0 ? data.base_composite : ld.composite[p]) += ld.composite[i].transformedBy(ld.liMi[i]);
  }
  data.M.template topLeftCorner<6, 6>() = data.base_composite.matrix();
  // Column j: F = Ic_j S_j carried up the chain; each ancestor k reads S_k^T F, the base all of F.
  for (int j = 0; j < n; ++j) {
    Vector6<Scalar> F = ld.composite[j].apply(jointMotionAt(limbs, j, Scalar(1)));
    data.M(6 + j, 6 + j) = projectOnJoint(limbs, j, F) + driveInertia(limbs, j);
    int i = j;
    for (int k = limbs.parents()[i]; k >= 0; i = k, k = limbs.parents()[k]) {
      F = ld.liMi[i].actForce(F);
      data.M(6 + k, 6 + j) = data.M(6 + j, 6 + k) = projectOnJoint(limbs, k, F);
    }
    F = ld.liMi[i].actForce(F);
    data.M.template block<6, 1>(0, 6 + j) = F;
    data.M.template block<1, 6>(6 + j, 0) = F.transpose();
  }
  return data.M;
}

template <typename Scalar>
const VectorX<Scalar>& floatingForwardDynamics(
    const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
    const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
    const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& tau,
    const std::type_identity_t<Vector6<Scalar>>& base_wrench) {
  checkFloatingData(model, data);
  checkSize(model.limbs(), tau, "tau");
  BaseMotionTpl<Scalar> still = base;
  still.acceleration.setZero();
  // h at zero acceleration: ddq is read as zeros from the acceleration buffer (sized 6 + n).
  data.acceleration.setZero();
  floatingRnea(model, data, still, q, dq, data.acceleration.tail(model.numJoints()));
  floatingCrba(model, data, q);
  data.acceleration.template head<6>() = base_wrench - data.tau.template head<6>();
  data.acceleration.tail(model.numJoints()) = tau - data.tau.tail(model.numJoints());
  data.llt.compute(data.M);
  data.llt.solveInPlace(data.acceleration);
  return data.acceleration;
}

}  // namespace dynid
