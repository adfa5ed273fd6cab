// What `dynid excite --stands K` adds to excitation.json, its report and its console summary: the
// stand orientations chosen for a suspended robot's design (analysis/floating/stand_tilts.hpp),
// and what each sensor set determines upright and at them.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/stand_tilts.hpp"
#include "reports/document.hpp"

namespace dynid {

/// The choice and the request's settings it was made with.
struct StandDesign {
  StandTiltChoice choice;
  double max_tilt = 0.0;
  int grid = 0, samples = 0;
};

/// excitation.json's `stand` (from version 5): tilts [[roll, pitch], ...] [rad] upright first,
/// the settings, the criterion, and per set its combinations and what upright and the chosen
/// orientations determine (condition null where not every one is).
nlohmann::json standJson(const StandDesign& stand);
/// The report's section: the orientations and a table of the sets.
void addStandSection(Document& doc, const StandDesign& stand);
/// Console lines, each ending in a newline.
std::string standSummary(const StandDesign& stand);

}  // namespace dynid
