// The built-in Franka Emika Panda: Franka's modified (Craig) Denavit-Hartenberg kinematics and
// joint limits, with the inertial parameters identified by Gaz et al. 2019 (docs/MODEL.md cites
// both). Rigid body only: Gaz et al. model the joints' friction by a sigmoid, which dynid's drive
// terms do not represent, so the drive parameters are 0 (identify them from data). Its link-side
// torque sensors never see the rotors: the drive terms it carries are fv, fc, fo (no Ia).
#pragma once

#include <Eigen/Core>

#include "core/model.hpp"
#include "data/dh.hpp"

namespace dynid {

/// The Panda's drive terms: viscous, Coulomb and a constant (sensor) offset, as Gaz et al.
inline constexpr DriveTerms kPandaDriveTerms =
    DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb, DriveTerm::kOffset});

/// The Panda's DH description (7 revolute joints, link parameters in the modified-DH link frames).
/// With `drives`, the drive terms kPandaDriveTerms (their values 0).
DhModel pandaDh(bool drives = false);
/// The Panda as a Model, named "panda".
Model makePanda(bool drives = false);

}  // namespace dynid
