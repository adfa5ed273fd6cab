// The built-in PUMA 560 (../shared/reference/puma560.md; Corke & Armstrong-Helouvry 1994, as in the
// Robotics Toolbox's mdl_puma560): standard Denavit-Hartenberg kinematics, no pedestal, gravity
// 9.81 m/s^2 along -z, link parameters in the DH link frames.
#pragma once

#include <Eigen/Core>

#include "core/model.hpp"

namespace dynid {

/// The PUMA 560. Rigid body only by default; with `drives` the joint-side rotor inertia
/// Ia = Jm G^2, viscous friction Fv = G^2 B, and the published asymmetric Coulomb friction
/// (|G| Tc+ for dq > 0, |G| Tc- for dq < 0) represented exactly by Fc = |G| (Tc+ - Tc-) / 2 and the
/// offset Fo = |G| (Tc+ + Tc-) / 2 (offsets enabled).
Model makePuma560(bool drives = false);

/// Named poses [rad]: "qz" (zero), "qr" (ready), "qs" (stretch), "qn" (nominal). Throws InputError
/// for any other name.
Eigen::VectorXd puma560Pose(const std::string& name);

}  // namespace dynid
