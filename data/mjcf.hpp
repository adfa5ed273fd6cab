// MuJoCo MJCF export of a Model, so that MuJoCo simulates exactly dynid's rigid-body dynamics
// (the peer benchmarks compare the two on the same model).
#pragma once

#include <string>
#include <vector>

#include "core/model.hpp"

namespace dynid {

struct MjcfOptions {
  double timestep = 1e-3;          // <option timestep>, [s]
  std::string integrator = "RK4";  // <option integrator>: RK4, Euler or implicit
  /// The model's drive terms that MJCF joints carry (the drive-term table's mjcf_joint: armature =
  /// Ia, damping = Fv, frictionloss = Fc) and its joint ranges (limited, range). Off: rigid-body
  /// dynamics only, as the peer benchmarks compare them.
  bool drives_and_limits = false;
};

/// The model as MJCF text, numbers in shortest round-trip form. Every MuJoCo body is a dynid joint
/// frame (body i's frame before its body placement), placed in its parent's joint frame, with a
/// hinge or slide joint at its origin along the joint axis and an <inertial> element (centre of
/// mass, mass, full inertia about the centre of mass). No geoms and no contacts; by default no
/// joint limits and none of dynid's drives (rotor inertia, friction): with qfrc_applied = tau,
/// MuJoCo's dynamics are then dynid's rigid-body ones (options.drives_and_limits adds them).
/// Gravity carries over. MuJoCo's compiler rejects bodies with a non-positive mass or an inertia
/// that violates the triangle inequality (the built-in PUMA's links 1 and 3, see `dynid model
/// check`): this function writes them as they are, and MuJoCo's error names the body.
std::string modelToMjcf(const Model& model, const MjcfOptions& options = {});

/// What an MJCF export of `model` with its drives cannot carry, one sentence each: the enabled
/// drive terms MJCF has no attribute for (Fo, Fa, Fs), and the links MuJoCo's compiler rejects
/// (mass not positive). Empty when it carries everything.
std::vector<std::string> mjcfCannotCarry(const Model& model);

/// MuJoCo numbers the joints of the exported model depth first (children in dynid order), which
/// differs from dynid's order for trees whose subtrees are not listed contiguously: entry k is the
/// dynid joint of MuJoCo's dof k (the identity for chains).
std::vector<int> mjcfJointOrder(const Model& model);

}  // namespace dynid
