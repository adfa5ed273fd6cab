#include "data/robots.hpp"

#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "data/urdf.hpp"

namespace dynid {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

bool isUrdfSpec(const std::string& spec) {
  return endsWith(spec, ".urdf") || endsWith(spec, ".xml");
}

Model loadRobot(const std::string& spec, const RobotOptions& options,
                std::vector<std::string>* warnings) {
  const bool drives = options.drives || options.drive_terms.has_value();
  if (!options.fixed_joints.empty() && !isUrdfSpec(spec))
    throw InputError("fixing joints applies to a URDF robot, not '" + spec + "'");
  Model model;
  if (spec == "puma560") {
    model = makePuma560(drives);
  } else if (spec == "puma560-consistent") {
    model = makePuma560Consistent(drives);
  } else if (spec == "panda") {
    model = makePanda(drives);
  } else if (isUrdfSpec(spec)) {
    model = loadUrdf(spec, {drives, options.strict, options.fixed_joints}, warnings);
  } else if (endsWith(spec, ".json")) {
    model = modelFromJson(readFile(spec), spec);
    if (options.drives && !model.driveTerms().any())
      model.setDriveTerms(DriveTerms::rotorAndFriction());
  } else {
    throw InputError(
        "unknown robot '" + spec +
        "': expected puma560, puma560-consistent, panda, a .urdf file or a dynid .json model");
  }
  if (options.drive_terms) model.setDriveTerms(*options.drive_terms);
  return model;
}

}  // namespace dynid
