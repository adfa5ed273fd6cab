// Joint friction law (parameters.hpp): tau_f = Fv dq + Fc sign(dq) + Fo + Fa |sign(dq)|, each term
// only when the model enables it.
#pragma once

#include "core/model.hpp"

namespace dynid {

/// sign(x) in {-1, 0, 1}; for dual numbers (ceres::Jet) the derivative part is zero.
template <typename Scalar>
inline Scalar signum(const Scalar& x) {
  if (x > Scalar(0)) return Scalar(1);
  if (x < Scalar(0)) return Scalar(-1);
  return Scalar(0);
}

/// Friction and offset torque of joint i at velocity dqi [rad/s]: the enabled terms of Fv dq +
/// Fc sign(dq) + Fo + Fa |sign(dq)|; zero when none is enabled.
template <typename Scalar>
inline Scalar jointFriction(const ModelTpl<Scalar>& model, int i, const Scalar& dqi) {
  const DriveTerms terms = model.drive_terms;
  if (!terms.friction()) return Scalar(0);
  const DriveParameters<Scalar>& d = model.drives()[i];
  const Scalar s = signum(dqi);
  Scalar out(0);
  if (terms.has(DriveTerm::kViscous)) out += d.viscous * dqi;
  if (terms.has(DriveTerm::kCoulomb)) out += d.coulomb * s;
  if (terms.has(DriveTerm::kOffset)) out += d.offset;
  if (terms.has(DriveTerm::kCoulombAsymmetry) && s != Scalar(0)) out += d.asymmetry;
  return out;
}

/// Joint i's drive torque: Ia ddq (when enabled) plus jointFriction.
template <typename Scalar>
inline Scalar driveTorque(const ModelTpl<Scalar>& model, int i, const Scalar& dqi,
                          const Scalar& ddqi) {
  Scalar out = jointFriction(model, i, dqi);
  if (model.drive_terms.has(DriveTerm::kRotorInertia))
    out += model.drives()[i].rotor_inertia * ddqi;
  return out;
}

}  // namespace dynid
