// Floating-base inverse dynamics, the mass matrix and forward dynamics (floating_model.hpp's
// conventions).
#pragma once

#include "core/floating/floating_data.hpp"

namespace dynid {

/// Inverse dynamics: the generalized force (w, tau) = M(q) (dnu, ddq) + h(q, nu, dq) (+ the
/// limbs' drive terms on tau), w the wrench (n, f) about the base origin in base-frame axes that
/// the motion needs from outside the robot. q, dq, ddq have n entries. Throws InputError on a size
/// mismatch or a Data built for another model. Overwrites data.limbs' liMi, data.motions,
/// base_motion, forces, base_v, base_a, base_f and tau. Returns data.tau (6 + n). Allocates
/// nothing.
template <typename Scalar>
const VectorX<Scalar>& floatingRnea(const FloatingModelTpl<Scalar>& model,
                                    FloatingDataTpl<Scalar>& data,
                                    const BaseMotionTpl<Scalar>& base,
                                    const ConstVectorRef<Scalar>& q,
                                    const ConstVectorRef<Scalar>& dq,
                                    const ConstVectorRef<Scalar>& ddq);

/// The mass matrix M(q) ((6 + n) square, symmetric, both triangles; rotor inertias Ia on the
/// joints' diagonal when enabled): the base block is the whole robot's composite inertia in the
/// base frame (independent of the base's pose: body coordinates). Throws InputError on a size
/// mismatch. Overwrites data.limbs' liMi and composite, data.base_composite, data.M. Returns
/// data.M. Allocates nothing.
template <typename Scalar>
const MatrixX<Scalar>& floatingCrba(const FloatingModelTpl<Scalar>& model,
                                    FloatingDataTpl<Scalar>& data, const ConstVectorRef<Scalar>& q);

/// Forward dynamics: (dnu, ddq) from the base's rotation and twist (its acceleration is ignored),
/// q, dq, the joint torques tau (n) and the external wrench on the base (about its origin, base
/// frame; zero for a robot in free fall), solving M (dnu, ddq) = (wrench, tau) - h with M's
/// Cholesky factor (floatingCrba, then floatingRnea at zero acceleration for h). Throws
/// InputError on a size mismatch. Returns data.acceleration (6 + n). Allocates nothing.
template <typename Scalar>
const VectorX<Scalar>& floatingForwardDynamics(
    const FloatingModelTpl<Scalar>& model, FloatingDataTpl<Scalar>& data,
    const BaseMotionTpl<Scalar>& base, const ConstVectorRef<Scalar>& q,
    const ConstVectorRef<Scalar>& dq, const ConstVectorRef<Scalar>& tau,
    const std::type_identity_t<Vector6<Scalar>>& base_wrench);

extern template const VectorX<double>& floatingRnea(const FloatingModel&, FloatingData&,
                                                    const BaseMotion&,
                                                    const ConstVectorRef<double>&,
                                                    const ConstVectorRef<double>&,
                                                    const ConstVectorRef<double>&);
extern template const MatrixX<double>& floatingCrba(const FloatingModel&, FloatingData&,
                                                    const ConstVectorRef<double>&);
extern template const VectorX<double>& floatingForwardDynamics(
    const FloatingModel&, FloatingData&, const BaseMotion&, const ConstVectorRef<double>&,
    const ConstVectorRef<double>&, const ConstVectorRef<double>&, const Vector6<double>&);

}  // namespace dynid
