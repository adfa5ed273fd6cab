// The generalized momentum p = M(q) dq and the observer's bias beta = g(q) + tau_f(dq) - C^T dq:
// what a momentum-based external-torque observer needs, dp/dt = tau + tau_ext - beta, with no
// joint acceleration.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// p = M(q) dq (rotor inertia Ia dq included when enabled) [N m s] and
/// beta = g(q) + tau_f(dq) - C(q, dq)^T dq [N m] (friction and offset when enabled), in one
/// recursive pass: with h_i = I_i v_i summed over each subtree into H_i,
///   p_k = S_k^T H_k,  C^T dq = dT/dq,  (dT/dq)_k = -S_k^T (v_k x* H_k),
///   g_k = S_k^T sum over the subtree of I_i a_g,i (a_g: -gravity carried to each body).
/// q, dq have n entries; p and beta are resized to n. Throws InputError on a size mismatch or a
/// Data of another model. Overwrites data.liMi, data.v, data.a (gravity forces), data.f (momenta).
template <typename Scalar>
void momentumTerms(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                   const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                   VectorX<Scalar>& p, VectorX<Scalar>& beta);

extern template void momentumTerms(const Model&, Data&, const ConstVectorRef<double>&,
                                   const ConstVectorRef<double>&, VectorX<double>&,
                                   VectorX<double>&);

}  // namespace dynid
