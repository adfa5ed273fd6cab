// Joint drive torques from the drive-term table (core/drive_terms.hpp): the sum of theta_k
// phi_k(dq, ddq) over the terms the model enables.
#pragma once

#include "core/model.hpp"

namespace dynid {

/// Friction and offset torque of joint i at velocity dqi [rad/s]: the enabled terms that are not
/// inertial (every one but Ia), in table order; zero when none is enabled.
template <typename Scalar>
inline Scalar jointFriction(const ModelTpl<Scalar>& model, int i, const Scalar& dqi) {
  const DriveTerms terms = model.driveTerms();
  if (!terms.friction()) return Scalar(0);
  const DriveParameters<Scalar>& d = model.drives()[i];
  Scalar out(0);
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k) && !kDriveTermTable[k].inertial)
      out += d.term(k) * driveBasis(k, dqi, Scalar(0));
  return out;
}

/// Joint i's drive torque: jointFriction plus the inertial terms (Ia ddq) when enabled.
template <typename Scalar>
inline Scalar driveTorque(const ModelTpl<Scalar>& model, int i, const Scalar& dqi,
                          const Scalar& ddqi) {
  Scalar out = jointFriction(model, i, dqi);
  const DriveTerms terms = model.driveTerms();
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k) && kDriveTermTable[k].inertial)
      out += model.drives()[i].term(k) * driveBasis(k, dqi, ddqi);
  return out;
}

/// The inertial drive terms' contribution to joint i's diagonal of the mass matrix (Ia).
template <typename Scalar>
inline Scalar driveInertia(const ModelTpl<Scalar>& model, int i) {
  const DriveTerms terms = model.driveTerms();
  Scalar out(0);
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k) && kDriveTermTable[k].inertial) out += model.drives()[i].term(k);
  return out;
}

}  // namespace dynid
