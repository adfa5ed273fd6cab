// What `dynid fleet` writes: fleet.json (the fleet's prior per base parameter, each robot's logs,
// estimate alone and with the prior, its z against the fleet and whether it lies outside, the
// verdict) and report.md / report.html (the verdict first, the robots outside and their
// parameters, the robots, the prior per parameter).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/fleet/fleet.hpp"

namespace dynid {

/// The document, without provenance (its writers stamp it).
nlohmann::json fleetJson(const FleetOutcome& outcome);
/// Writes fleet.json and the report into `dir` as one set. Returns the console summary.
std::string writeFleet(const std::string& dir, const FleetOutcome& outcome);

}  // namespace dynid
