// One entry point for "--robot R": the built-in PUMA 560, a URDF file, or a dynid JSON model.
#pragma once

#include <string>
#include <vector>

#include "core/model.hpp"

namespace dynid {

struct RobotOptions {
  bool drives =
      false;  // enable rotor inertia and friction (PUMA: published values; URDF: <dynamics>)
  bool strict = false;  // URDF warnings become errors
};

/// "puma560" or "puma560-consistent" (built in, data/puma560.hpp), "panda" (data/panda.hpp), a path
/// ending in .urdf, or a
/// path ending in .json (modelToJson format). Throws InputError for anything else, ParseError for a
/// malformed file. For a JSON model, `drives` enables its drives if the file has them disabled
/// (never disables them).
Model loadRobot(const std::string& spec, const RobotOptions& options = {},
                std::vector<std::string>* warnings = nullptr);

}  // namespace dynid
