// A fleet manifest read back (dynid fleet --manifest): the robots of a fleet and their logs or
// summaries, for robots whose files do not lie in a folder each.
//   {"schema_version": 1, "kind": "dynid.fleet_manifest",
//    "robots": [{"name": "robot_a", "data": ["shift1/a.csv", "shift2/a.csv"]},
//               {"name": "robot_b", "summaries": ["sums/b.summary.json"]}]}
// A relative path is relative to the manifest's folder (it runs the same from any directory).
#pragma once

#include <string>
#include <vector>

namespace dynid {

struct FleetManifestRobot {
  std::string name;
  std::vector<std::string> data, summaries;  // one of the two, not empty
};

/// The manifest's robots in order. Throws ParseError naming the file and the field: an unknown
/// key, a robot without a name or with an empty one, two robots of one name, a robot with both
/// `data` and `summaries` or neither, an empty or non-string path.
std::vector<FleetManifestRobot> fleetManifestFrom(const std::string& text, const std::string& file);
/// The same from the file (read through data/io's readFile: a command's input).
std::vector<FleetManifestRobot> readFleetManifest(const std::string& file);

}  // namespace dynid
