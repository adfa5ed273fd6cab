// Models as JSON: every number of a Model (kinematics, both placements, inertial and drive
// parameters, limits, gravity), exactly, so export -> load reproduces the model bit for bit.
//
// {"schema_version": 1, "kind": "dynid.model", "name": ..., "gravity": [gx, gy, gz],
//  "drives": bool, "offsets": bool,
//  "bodies": [{"name", "parent" (name or null), "joint": {"name", "type", "axis": [3],
//              "placement": {"rotation": [[3],[3],[3]], "translation": [3]},
//              "body_placement": {...}, "limits": {"lower", "upper", "velocity", "effort"}
//              (null = unlimited)},
//              "inertial": {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"},
//              "drive": {"Ia", "Fv", "Fc", "Fo"}}]}
#pragma once

#include <string>

#include "core/model.hpp"

namespace dynid {

inline constexpr int kModelSchemaVersion = 1;

/// The model as JSON text (pretty-printed, numbers in shortest round-trip form).
std::string modelToJson(const Model& model);

/// Parses a model from JSON text. `file` names the source in errors. Throws ParseError naming the
/// JSON path at fault (e.g. "bodies[2].joint.axis") for missing or mistyped fields, non-finite
/// numbers, unknown parents or joint types, negative masses; the model is finalized.
Model modelFromJson(const std::string& text, const std::string& file);

}  // namespace dynid
