// The built-in Franka Emika Panda: Franka's modified (Craig) Denavit-Hartenberg kinematics and
// joint limits, with the inertial parameters identified by Gaz et al. 2019 (docs/MODEL.md cites
// both). Rigid body only: Gaz et al. model the joints' friction by a sigmoid, which dynid's drive
// terms do not represent, so the drive parameters are 0 (identify them from data).
#pragma once

#include <Eigen/Core>

#include "core/model.hpp"
#include "data/dh.hpp"

namespace dynid {

/// The Panda's DH description (7 revolute joints, link parameters in the modified-DH link frames).
DhModel pandaDh(bool drives = false);
/// The Panda as a Model, named "panda".
Model makePanda(bool drives = false);

}  // namespace dynid
