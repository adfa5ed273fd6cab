// Joint drive torques from the drive-term table (core/drive_terms.hpp): the sum of theta_k
// phi_k(dq, ddq) over the terms the model enables.
#pragma once

#include <algorithm>
#include <limits>
#include <utility>

#include "core/model.hpp"

namespace dynid {

/// Friction and offset torque of joint i at velocity dqi [rad/s]: the enabled terms that are not
/// inertial (every one but Ia), in table order; zero when none is enabled. Within joint i's rest
/// velocity the terms that need sign(dq) take their point value at rest, zero (drive_terms.hpp).
template <typename Scalar>
inline Scalar jointFriction(const ModelTpl<Scalar>& model, int i, const Scalar& dqi) {
  const DriveTerms terms = model.driveTerms();
  if (!terms.friction()) return Scalar(0);
  const DriveParameters<Scalar>& d = model.drives()[i];
  Scalar out(0);
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k) && !kDriveTermTable[k].inertial)
      out += d.term(k) * driveBasis(k, dqi, Scalar(0), model.restVelocity(i));
  return out;
}

/// The static friction band of joint i at rest: the terms that need sign(dq) take any value
/// between their one-sided limits at dq -> 0- and dq -> 0+ (Fc + Fa + Fs and -Fc + Fa - Fs for
/// the table's laws), zero included; {lo, hi} with lo <= 0 <= hi [N m or N].
inline std::pair<double, double> staticFrictionBand(const ModelTpl<double>& model, int i) {
  const DriveTerms terms = model.driveTerms();
  double side[2] = {0.0, 0.0};
  const double tiny = std::numeric_limits<double>::min();
  for (int k = 0; k < kDriveTermCount; ++k)
    if (terms.has(k) && kDriveTermTable[k].signed_by_velocity)
      for (int s = 0; s < 2; ++s)
        side[s] += model.drives()[i].term(k) * driveBasis(k, s == 0 ? -tiny : tiny, 0.0);
  return {std::min({0.0, side[0], side[1]}), std::max({0.0, side[0], side[1]})};
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
