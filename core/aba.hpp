// Articulated-body algorithm: forward dynamics.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Forward dynamics: ddq = M(q)^-1 (tau - C(q, dq) dq - g(q) - friction(dq)), with the rotor
/// inertias Ia added to M when the model's drives are enabled. q, dq, tau have n entries each.
/// Throws InputError on a size mismatch. A massless subtree on a joint without rotor inertia makes
/// M singular and gives non-finite ddq. Overwrites data.liMi, data.v, data.a, data.c, data.U,
/// data.U_parent, data.D, data.D_inv, data.u, data.u_minus_Uc, data.articulated_inertia (the
/// joints with children; data.articulated_written says which), data.bias_force, data.ddq. Returns
/// data.ddq. Allocates nothing.
template <typename Scalar>
const VectorX<Scalar>& aba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                           const ConstVectorRef<Scalar>& tau);

extern template const VectorX<double>& aba(const Model&, Data&, const ConstVectorRef<double>&,
                                           const ConstVectorRef<double>&,
                                           const ConstVectorRef<double>&);

}  // namespace dynid
