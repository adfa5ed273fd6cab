// Models as JSON: every number of a Model (kinematics, both placements, inertial and drive
// parameters, limits, gravity), exactly, so export -> load reproduces the model bit for bit.
//
// {"schema_version": 1, "kind": "dynid.model", "name": ..., "gravity": [gx, gy, gz],
//  "drive_terms": ["ia", "fv", "fc", "fo", "fa"] (any subset, core/parameters.hpp; absent or []:
//  none; the older "drives": bool is read as ["ia", "fv", "fc"]),
//  "bodies": [{"name", "parent" (name or null), "joint": {"name", "type", "axis": [3],
//              "placement": {"rotation": [[3],[3],[3]], "translation": [3]},
//              "body_placement": {...}, "limits": {"lower", "upper", "velocity", "effort"}
//              (null = unlimited)},
//              "inertial": {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"},
//              "drive": {"Ia", "Fv", "Fc", "Fo", "Fa"} (a missing one is 0)}]}
//
// Or, instead of "bodies", a Denavit-Hartenberg chain (data/dh.hpp):
//  "dh": {"convention": "standard" | "modified",
//         "inertia_about": "com" | "origin",
//         "joints": [{"name", "link", "type", "a", "d", "alpha", "theta_offset" (default 0),
//                     "limits": {"lower", "upper", "velocity", "acceleration", "effort"},
//                     "inertial": with "com": {"m", "com": [3], "inertia": {"Ixx", "Ixy", "Ixz",
//                                 "Iyy", "Iyz", "Izz"}} (about the centre of mass, link axes);
//                                 with "origin": {"m", "mx", ..., "Izz"} (about the frame origin),
//                     "drive": {"Ia", "Fv", "Fc", "Fo", "Fa"}}]}
// in the DH link frames, SI units and radians. Unknown keys are errors (a misspelt key must not
// silently become a default); limits may be omitted or null (unlimited).
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
