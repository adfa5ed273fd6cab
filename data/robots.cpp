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

/// A URDF loaded without drive options whose <dynamics> carry damping or friction (as dynid's own
/// write-back fills them): those are its joints' viscous and Coulomb friction, read back as Fv and
/// Fc, and said so. A rigid model would ignore what the file states.
void readBackUrdfFriction(const std::string& spec, Model& model,
                          std::vector<std::string>* warnings) {
  std::string joints;
  for (int j = 0; j < model.numJoints(); ++j) {
    const DriveParameters<double>& d = model.drives()[j];
    if (d[DriveTerm::kViscous] != 0.0 || d[DriveTerm::kCoulomb] != 0.0)
      joints += (joints.empty() ? "" : ", ") + model.joint_names[j];
  }
  if (joints.empty()) return;
  model.setDriveTerms(DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb}));
  if (warnings)
    warnings->push_back(spec +
                        ": its <dynamics> damping and friction are read as viscous and Coulomb "
                        "friction (drive terms fv,fc; nonzero on " +
                        joints + "); `drive_terms` none gives the rigid model");
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
    if (!drives) readBackUrdfFriction(spec, model, warnings);
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

FloatingModel loadFloatingRobot(const std::string& spec, const RobotOptions& options,
                                std::vector<std::string>* warnings) {
  if (!isUrdfSpec(spec))
    throw InputError("a floating-base robot is read from a URDF file, not '" + spec +
                     "' (the built-in arms are fixed to their base)");
  const bool drives = options.drives || options.drive_terms.has_value();
  FloatingModel model =
      loadFloatingUrdf(spec, {drives, options.strict, options.fixed_joints}, warnings);
  if (options.drive_terms) model.setDriveTerms(*options.drive_terms);
  return model;
}

}  // namespace dynid
