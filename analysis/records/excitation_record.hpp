// excitation.json (dynid excite, rendered by reports/excitation_report) read back: the design a
// simulation tracks or a study's training motion follows.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/controllers.hpp"

namespace dynid {

/// The design of an excitation.json written by `dynid excite`, read strictly (schema_version,
/// kind, unknown top-level keys, the design's fields and ranges) for a robot of `num_joints`
/// joints (0: as many as the design has). Throws ParseError naming `file` and the field.
FourierSeries excitationDesignFrom(const nlohmann::json& document, const std::string& file,
                                   int num_joints);
/// The same from the file at `path` (readFile's limits apply).
FourierSeries readExcitationDesign(const std::string& path, int num_joints);

}  // namespace dynid
