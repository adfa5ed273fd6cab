// Template body of floating_aba.hpp; include only to instantiate a new Scalar.
#pragma once

#include <Eigen/Cholesky>

#include "core/aba-inl.hpp"
#include "core/crba-inl.hpp"
#include "core/floating/floating_aba.hpp"

namespace dynid {

template <typename Scalar>
const VectorX<Scalar>& floatingAba(const FloatingModelTpl<Scalar>& model,
                                   FloatingDataTpl<Scalar>& data, const BaseMotionTpl<Scalar>& base,
                                   const ConstVectorRef<Scalar>& q,
                                   const ConstVectorRef<Scalar>& dq,
                                   const ConstVectorRef<Scalar>& tau,
                                   const std::type_identity_t<Vector6<Scalar>>& base_wrench) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkState(limbs, ld, q, dq, tau, "tau");
  const int n = limbs.numJoints();
  setJointTransformsBlock(limbs, ld.liMi, q);
  // The base body: its twist, rigid-body inertia and bias force v x* I v.
  data.base_v = base.twist;
  const RigidInertia<Scalar>& I = model.baseInertia();
  data.base_articulated = I.matrix();
  const Vector3<Scalar> w = base.twist.template head<3>(), vl = base.twist.template tail<3>();
  const Vector3<Scalar> hw = I.inertia * w + cross(I.first_moment, vl);
  const Vector3<Scalar> hv = I.mass * vl - cross(I.first_moment, w);
  data.base_bias.template head<3>() = cross(w, hw) + cross(vl, hv);
  data.base_bias.template tail<3>() = cross(w, hv);
  aba_detail::AbaRoot<Scalar> root;
  root.twist = &data.base_v;
  root.inertia = &data.base_articulated;
  root.bias = &data.base_bias;
  root.acceleration = &data.base_a;
  aba_detail::abaVelocityPass<true>(limbs, ld, dq, tau, root);
  aba_detail::abaInertiaPass<true>(limbs, ld, root);
  // IA_0 a_0 = wrench - pA_0, a_0 the base's acceleration with gravity as -g (what the limbs'
  // bias forces leave out); dnu = a_0 + R^T g.
  data.base_a = Eigen::LLT<Matrix6<Scalar>>(data.base_articulated)
                    .solve(Vector6<Scalar>(base_wrench - data.base_bias));
  aba_detail::abaAccelerationPass<true>(limbs, ld, root);
  data.acceleration.template head<6>() = data.base_a;
  data.acceleration.template segment<3>(3) += transposeTimes(base.rotation, model.gravity());
  data.acceleration.tail(n) = ld.ddq;
  return data.acceleration;
}

}  // namespace dynid
