// Documents of an earlier schema version rewritten in the current one (`dynid upgrade`): the
// records wing knows every document's versions (document.hpp), so it is where they migrate. Each
// version's change is applied in turn; what an older version did not record stays absent (its
// readers take it as they always did: no rest velocities, a white covariance, no provenance, ...),
// and the outcome's notes say so. Upgraded: estimate.json 1-5 (the robot embedded, loaded from its
// robot_spec beside the document, or `robot_spec`), excitation.json 1-3, thresholds.json 1-4 and
// search.json 1-2 (the robot of an excitation before 3, thresholds before 4 and a search before 2
// is not embedded: they record its name, not its file and drive terms; the notes say so); and the
// documents no command reads back, for their readers (scripts, people): prediction.json 1-5
// (version 1's per-joint errors renamed as version 2 names them), payload.json 1-3, its body 1,
// monitor.json 1-5, audit.json 1-3, study.json 1-2, refine.json 1-2, prepare.json 1-2 (version 1's
// sources.table a list), identifiability.json 1 and the demo's summary 1.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dynid {

struct UpgradeRequest {
  std::string file;        // the document
  std::string robot_spec;  // an estimate's robot, where its robot_spec is not found
};

struct UpgradeOutcome {
  nlohmann::json document;         // in the current version (the same when it already was)
  std::string kind;                // "dynid.estimate", ...
  int from = 0, to = 0;            // its version before and after
  std::vector<std::string> notes;  // one per change made or field left absent
};

/// Reads `request.file` and brings it to its kind's current version. Throws ParseError for a file
/// that is not a dynid document of a kind that has earlier versions (naming the kinds that do),
/// InputError for a version later than this dynid's (written by a newer dynid) or a robot that
/// cannot be loaded (naming `robot_spec`).
UpgradeOutcome upgradeDocument(const UpgradeRequest& request);

/// One line for a reader of an older document: "FILE is KIND version N (current M): read as it
/// is; upgrading the document rewrites it in version M" (the front ends name their upgrade).
std::string olderVersionNote(const std::string& file, const std::string& kind, int version,
                             int current);

}  // namespace dynid
