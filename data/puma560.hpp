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
/// Coulomb asymmetry Fa = |G| (Tc+ + Tc-) / 2: drive terms kPuma560DriveTerms.
Model makePuma560(bool drives = false);

/// ia, fv, fc, fa: the PUMA 560's published drive model (Corke and Armstrong-Helouvry).
inline constexpr DriveTerms kPuma560DriveTerms =
    DriveTerms::of({DriveTerm::kRotorInertia, DriveTerm::kViscous, DriveTerm::kCoulomb,
                    DriveTerm::kCoulombAsymmetry});

/// The built-in PUMA 560 made physically consistent, for engines that refuse the original (MuJoCo)
/// and for comparisons that need a realisable body: link 1 (massless, rank-1 inertia) gets 1 kg at
/// its origin, which lies on joint 1's axis, and the isotropic inertia 0.35 kg m^2, so every joint
/// torque is unchanged; link 3 (0.066 + 0.0125 < 0.086, the triangle inequality fails) gets its
/// smallest principal inertia about the centre of mass raised from 0.0125 to 0.0215 kg m^2, which
/// does change its dynamics. Named "puma560-consistent".
Model makePuma560Consistent(bool drives = false);

/// Named poses [rad]: "qz" (zero), "qr" (ready), "qs" (stretch), "qn" (nominal). Throws InputError
/// for any other name.
Eigen::VectorXd puma560Pose(const std::string& name);

}  // namespace dynid
