// One entry point for "--robot R": the built-in PUMA 560, a URDF file, or a dynid JSON model.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/floating/floating_model.hpp"
#include "core/model.hpp"

namespace dynid {

struct RobotOptions {
  /// `--drives`: the robot's own drive terms (puma560: ia,fv,fc,fa with the published values;
  /// panda: fv,fc,fo; a JSON model: its "drive_terms", or ia,fv,fc when it names none; a URDF:
  /// ia,fv,fc with Fv, Fc from <dynamics>).
  bool drives = false;
  /// `--drive-terms`: exactly these terms (values from the robot where it has them, else 0).
  /// Overrides `drives`.
  std::optional<DriveTerms> drive_terms;
  bool strict = false;  // URDF warnings become errors
  /// A URDF's moving joints treated as fixed at zero (UrdfOptions::fixed_joints); InputError for
  /// another kind of robot.
  std::vector<std::string> fixed_joints = {};
};

/// "puma560" or "puma560-consistent" (built in, data/puma560.hpp), "panda" (data/panda.hpp), a path
/// ending in .urdf, or a
/// path ending in .json (modelToJson format). Throws InputError for anything else, ParseError for a
/// malformed file. Drive terms: RobotOptions; without either option a built-in robot is rigid, a
/// JSON model keeps its file's terms, and a URDF is rigid unless its <dynamics> carry damping or
/// friction: those are read as fv,fc (Fv = damping, Fc = friction), with a warning that says so.
/// Whether a robot spec names a URDF file (ends in .urdf or .xml).
bool isUrdfSpec(const std::string& spec);

Model loadRobot(const std::string& spec, const RobotOptions& options = {},
                std::vector<std::string>* warnings = nullptr);

/// A floating-base robot (`floating_base`): a URDF file through loadFloatingUrdf, its limbs' drive
/// terms as loadRobot gives a URDF's. Throws InputError for any other robot (the built-in arms
/// are fixed-base; a dynid JSON model has no floating form yet), ParseError for a malformed file.
FloatingModel loadFloatingRobot(const std::string& spec, const RobotOptions& options = {},
                                std::vector<std::string>* warnings = nullptr);

}  // namespace dynid
