// Joint friction law (parameters.hpp): tau_f = Fv dq + Fc sign(dq) + Fo |sign(dq)|.
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

/// Friction torque of joint i at velocity dqi [rad/s]; zero when the model's drives are disabled.
template <typename Scalar>
inline Scalar jointFriction(const ModelTpl<Scalar>& model, int i, const Scalar& dqi) {
  if (!model.drives_enabled) return Scalar(0);
  const DriveParameters<Scalar>& d = model.drives()[i];
  const Scalar s = signum(dqi);
  Scalar out = d.viscous * dqi + d.coulomb * s;
  if (model.offsets_enabled && s != Scalar(0)) out += d.offset;
  return out;
}

}  // namespace dynid
