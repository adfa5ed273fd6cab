// Floating-base forward dynamics by the articulated-body algorithm (Featherstone, "Rigid Body
// Dynamics Algorithms", 2008, section 9.2): O(n), against floatingForwardDynamics' O(n^3) solve
// with the mass matrix (floating_rnea.hpp), which it equals.
#pragma once

#include "core/floating/floating_data.hpp"

namespace dynid {

/// Forward dynamics: (dnu, ddq) from the base's rotation and twist (its acceleration is ignored),
/// q, dq, the joint torques tau (n) and the external wrench on the base (about its origin, base
/// frame; zero for a robot in free fall), as floatingForwardDynamics; the limbs' drive terms
/// (friction, rotor inertia) as aba's. The limbs' articulated inertias are handed to the base,
/// whose acceleration is the one 6x6 solve, then the joints' accelerations follow root to leaves.
/// Throws InputError on a size mismatch or a Data built for another model. Overwrites data.limbs'
/// ABA fields (core/aba.hpp), data.base_v, base_a, base_articulated, base_bias and
/// data.acceleration. Returns data.acceleration (6 + n). Allocates nothing.
template <typename Scalar>
const VectorX<Scalar>& floatingAba(const FloatingModelTpl<Scalar>& model,
                                   FloatingDataTpl<Scalar>& data, const BaseMotionTpl<Scalar>& base,
                                   const ConstVectorRef<Scalar>& q,
                                   const ConstVectorRef<Scalar>& dq,
                                   const ConstVectorRef<Scalar>& tau,
                                   const std::type_identity_t<Vector6<Scalar>>& base_wrench);

extern template const VectorX<double>& floatingAba(const FloatingModel&, FloatingData&,
                                                   const BaseMotion&, const ConstVectorRef<double>&,
                                                   const ConstVectorRef<double>&,
                                                   const ConstVectorRef<double>&,
                                                   const Vector6<double>&);

}  // namespace dynid
