// A known body attached to a link of a model (dynid model attach): a tool of known mass, centre of
// mass and inertia, or a payload estimate (payload.body.json), carried by the arm for simulation,
// for a loaded/unloaded pair, or as the model of the arm with its tool.
#pragma once

#include <string>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/parameters.hpp"
#include "core/spatial.hpp"
#include "identifiability/payload.hpp"

namespace dynid {

/// The link a payload or body is attached to: `link` by name among the moving links, the last for
/// "". Throws InputError naming `link` and listing the robot's links.
int linkIndex(const Model& arm, const std::string& link);

/// A body's 10 standard parameters in its frame from its mass [kg], centre of mass [m] and inertia
/// about the centre of mass in the frame's axes [kg m^2]. Throws InputError naming `mass` (not
/// finite and > 0), `com` (not finite) or `inertia` (not symmetric positive semidefinite, or its
/// principal moments break the triangle inequality: no rigid body has it).
Vector10d bodyFromCentre(double mass, const Eigen::Vector3d& com,
                         const Eigen::Matrix3d& inertia_about_com);

/// `arm` with `body` (standard parameters in `frame`, a frame of link `link`) added to that link's
/// inertia: the loaded arm, every other parameter (drive terms, limits, rest velocities) kept.
Model attachBody(const Model& arm, int link, const Pose<double>& frame, const Vector10d& body);

}  // namespace dynid
