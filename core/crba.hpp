// Composite rigid-body algorithm: the joint-space mass matrix.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Mass matrix M(q) (n x n, symmetric, both triangles filled), including the rotor inertias Ia on
/// the diagonal when the model's drives are enabled. q has n entries. Throws InputError on a size
/// mismatch. Overwrites data.liMi, data.composite, data.column_force, data.column_frame, data.M.
/// Returns data.M. Allocates nothing. For double, the joints' sines and cosines come from
/// sinCosBlock (core/sin_cos.hpp: within 1 ulp, the same bits on every CPU, all joints at once in
/// SIMD registers), not from the C library as in the other algorithms, so M can differ from one
/// assembled from RNEA in the last bits.
template <typename Scalar>
const MatrixX<Scalar>& crba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q);

extern template const MatrixX<double>& crba(const Model&, Data&, const ConstVectorRef<double>&);

}  // namespace dynid
