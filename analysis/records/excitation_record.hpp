// excitation.json (dynid excite, rendered by reports/excitation_report) read back: the design a
// simulation tracks or a study's training motion follows.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

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

/// The stand orientations an excitation.json chose for its design (`stand.tilts`, version 5, each
/// (roll, pitch) [rad] within +-pi/2, at most 16); none where `stand` is null or absent (versions
/// before 5). Throws ParseError naming `file` and the field.
std::vector<Eigen::Vector2d> excitationStandTiltsFrom(const nlohmann::json& document,
                                                      const std::string& file);

/// A standing robot's designed sway (standing_excitation.json, `dynid excite --floating-base
/// --stance`): the contacts as given (NAME, NAME:frame), the joints at rest and the base's six
/// coordinates (analysis/floating/standing.hpp's StandingMotionRequest::base_design).
struct StandingDesignRecord {
  std::vector<std::string> contacts;
  Eigen::VectorXd stance;
  FourierSeries base;
  std::optional<FourierSeries> joints;  // the joints no foot depends on (`joint_design`), if any
};
/// Read strictly for a robot of `num_joints` joints (0: as many as the stance has). Throws
/// ParseError naming `file` and the field.
StandingDesignRecord standingDesignFrom(const nlohmann::json& document, const std::string& file,
                                        int num_joints);

/// A design and its stand orientations from one reading of the file at `path`, or, for a
/// standing_excitation.json, its standing design (`design` then empty).
struct ExcitationDesignFile {
  FourierSeries design;
  std::vector<Eigen::Vector2d> stand_tilts;
  std::optional<StandingDesignRecord> standing;
};
ExcitationDesignFile readExcitationDesignFile(const std::string& path, int num_joints);

}  // namespace dynid
