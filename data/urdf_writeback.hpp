// URDF write-back: a copy of a robot's own URDF text carrying identified parameters, everything
// else (joints, limits, meshes, materials, comments, unknown tags, formatting) byte for byte.
//
// dynid merges links attached by fixed joints into their moving parent's body (data/urdf.hpp), so
// an identified body is the moving link plus its fixed children. The fixed children keep their
// <inertial> unchanged and the moving link gets the rest: identified body minus fixed children,
// written as mass, centre of mass (<origin xyz>, rpy 0) and the inertia about the centre of mass
// in link axes. Reloading the written file therefore gives the identified bodies again (to the
// round-off of the shortest round-trip decimal form). Joints get <dynamics damping="Fv"
// friction="Fc"> where the model carries those terms; URDF has no place for Ia, Fo or Fa (write
// the model as dynid JSON for those).
#pragma once

#include <string>

#include "core/model.hpp"

namespace dynid {

/// `urdf_text` (the file `file`, from which `identified` was loaded: same link and joint names)
/// with each moving link's <inertial> and each moving joint's <dynamics> replaced as above (added
/// when missing). Throws InputError when a body of `identified` is not physically consistent, or
/// when its fixed children outweigh it (the moving link's remainder is not a realisable body),
/// naming the link; ParseError when the text cannot be read or its links do not match the model.
std::string urdfWithParameters(const std::string& urdf_text, const std::string& file,
                               const Model& identified);

/// `urdf_text` (the file `file`) with a rigid body added as a link fixed to `parent_link` at
/// `origin` (the body's frame in the parent link's frame; its inertial written about its centre
/// of mass in its own axes), named `name` (or name_2, ... when taken), everything else byte for
/// byte. The body's frame holds its parameters. Throws InputError for a body that is not
/// physically consistent, ParseError when the parent link is not in the file.
std::string urdfWithFixedBody(const std::string& urdf_text, const std::string& file,
                              const std::string& parent_link, const std::string& name,
                              const Pose<double>& origin, const RigidInertia<double>& body);

}  // namespace dynid
