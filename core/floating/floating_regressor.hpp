// The floating-base regressor: (w, tau) = Y(base, q, dq, ddq) theta, linear in the floating
// standard parameters (floating_model.hpp: the base body's 10, then the limbs').
#pragma once

#include "core/floating/floating_data.hpp"

namespace dynid {

/// Fills data.Y ((6 + n) x numParameters()) so that Y theta = floatingRnea(...) for any theta:
/// rows 0-5 the base wrench (n, f), rows 6.. the joint torques; column block 0-9 the base body,
/// then the limbs' columns as jointTorqueRegressor orders them. The base rows see every body's
/// inertial parameters and no drive term (the drives act between links). Y does not depend on the
/// model's parameter values. Throws InputError on a size mismatch. Overwrites data.limbs' liMi,
/// oMj, data.motions, base_motion, base_axes, base_v, base_a and data.Y's structurally non-zero
/// entries: the others are zero from the Data's construction and never written, so the caller must
/// not write data.Y (copy it). Returns data.Y. Allocates nothing.
template <typename Scalar>
const RowMatrixX<Scalar>& floatingRegressor(const FloatingModelTpl<Scalar>& model,
                                            FloatingDataTpl<Scalar>& data,
                                            const BaseMotionTpl<Scalar>& base,
                                            const ConstVectorRef<Scalar>& q,
                                            const ConstVectorRef<Scalar>& dq,
                                            const ConstVectorRef<Scalar>& ddq);

extern template const RowMatrixX<double>& floatingRegressor(const FloatingModel&, FloatingData&,
                                                            const BaseMotion&,
                                                            const ConstVectorRef<double>&,
                                                            const ConstVectorRef<double>&,
                                                            const ConstVectorRef<double>&);

}  // namespace dynid
