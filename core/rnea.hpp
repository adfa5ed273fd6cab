// Recursive Newton-Euler inverse dynamics.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Inverse dynamics: tau = M(q) ddq + C(q, dq) dq + g(q) (+ Ia ddq + friction(dq) when the model's
/// drives are enabled). q, dq, ddq have n entries each (rad, rad/s, rad/s^2; m for prismatic).
/// Throws InputError on a size mismatch or a Data built for another model; non-finite inputs give
/// non-finite outputs. Overwrites data.liMi, data.v, data.a, data.f, data.tau. Returns data.tau.
/// Allocates nothing.
template <typename Scalar>
const VectorX<Scalar>& rnea(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q, const ConstVectorRef<Scalar>& dq,
                            const ConstVectorRef<Scalar>& ddq);

extern template const VectorX<double>& rnea(const Model&, Data&, const ConstVectorRef<double>&,
                                            const ConstVectorRef<double>&,
                                            const ConstVectorRef<double>&);

}  // namespace dynid
