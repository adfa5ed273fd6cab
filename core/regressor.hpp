// The joint torque regressor: tau = Y(q, dq, ddq) theta, linear in the standard parameters theta
// (order and names: core/parameters.hpp).
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Fills data.Y (n x parameterLayout().size()) so that Y theta = rnea(model, data, q, dq, ddq) for
/// the model's own theta and for any other theta: link i's 10 columns are those of its standard
/// parameters in its link frame, followed (with drives) by joint i's Ia (ddq_i), Fv (dq_i),
/// Fc (sign dq_i) and, with offsets, Fo (|sign dq_i|). Y does not depend on the model's parameter
/// values. q, dq, ddq have n entries. Throws InputError on a size mismatch. Overwrites data.liMi,
/// data.v, data.a, data.Y. Returns data.Y. Allocates nothing.
template <typename Scalar>
const MatrixX<Scalar>& jointTorqueRegressor(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                            const ConstVectorRef<Scalar>& q,
                                            const ConstVectorRef<Scalar>& dq,
                                            const ConstVectorRef<Scalar>& ddq);

extern template const MatrixX<double>& jointTorqueRegressor(const Model&, Data&,
                                                            const ConstVectorRef<double>&,
                                                            const ConstVectorRef<double>&,
                                                            const ConstVectorRef<double>&);

}  // namespace dynid
