#include "reports/stand_tilts_report.hpp"

#include <cmath>
#include <sstream>

#include "core/format.hpp"
#include "data/json_number.hpp"

namespace dynid {

namespace {

const char* kCriterion =
    "the unit-column condition number of the support's six rows (the wrenches set) over the "
    "design at every orientation; upright first, then each orientation the one that lowers it "
    "most, then exchanges while one lowers it";

nlohmann::json scoreJson(const StandSetScore& s) {
  return {{"determined", s.determined}, {"condition", numberOrNull(s.condition)}};
}

std::string tiltText(const Eigen::Vector2d& tilt) {
  return "(" + formatNumber(tilt[0], 4) + ", " + formatNumber(tilt[1], 4) + ")";
}

std::string tiltsText(const StandDesign& stand) {
  std::string out;
  for (std::size_t k = 0; k < stand.choice.tilts.size(); ++k)
    out += (k ? ", " : "") + tiltText(stand.choice.tilts[k]);
  return out;
}

/// "80 of 80, condition 81.8" or "79 of 80".
std::string scoreText(const StandSetScore& s) {
  return std::to_string(s.determined) + " of " + std::to_string(s.combinations) +
         (std::isfinite(s.condition) ? ", condition " + formatNumber(s.condition, 4) : "");
}

}  // namespace

nlohmann::json standJson(const StandDesign& stand) {
  const StandTiltChoice& c = stand.choice;
  nlohmann::json tilts = nlohmann::json::array(), added = nlohmann::json::array(),
                 sets = nlohmann::json::array();
  for (const Eigen::Vector2d& t : c.tilts) tilts.push_back({t[0], t[1]});
  for (double x : c.condition_added) added.push_back(numberOrNull(x));
  for (std::size_t s = 0; s < c.chosen.size(); ++s)
    sets.push_back({{"set", sensorSetName(c.chosen[s].set)},
                    {"combinations", c.chosen[s].combinations},
                    {"upright", scoreJson(c.upright[s])},
                    {"chosen", scoreJson(c.chosen[s])}});
  return {{"tilts", tilts},
          {"form",
           "(roll, pitch) [rad] of the stand, yaw 0 (rotationFromRpy); the design run "
           "once at each in turn"},
          {"max_tilt", stand.max_tilt},
          {"grid", stand.grid},
          {"samples", stand.samples},
          {"candidates", c.candidates},
          {"criterion", kCriterion},
          {"condition", numberOrNull(c.condition)},
          {"condition_added", added},
          {"exchanges", c.exchanges},
          {"sets", sets}};
}

void addStandSection(Document& doc, const StandDesign& stand) {
  const StandTiltChoice& c = stand.choice;
  doc.heading("Stand orientations");
  doc.paragraph(
      "For the robot suspended on a stand with a force-torque sensor under its base: run the "
      "design once at each of these stand orientations (roll, pitch) [rad], upright first: " +
      tiltsText(stand) + ". Chosen among " + std::to_string(c.candidates) +
      " candidates (roll and pitch each on " + std::to_string(stand.grid) + " points within +-" +
      formatNumber(stand.max_tilt) + " rad) by " + kCriterion + " (" +
      std::to_string(stand.samples) +
      " states of the design at each). A base that never tilts "
      "sees gravity from one side: its support's rows cannot show the whole body's first moment "
      "along gravity. A floating-base simulation of this design runs it at these orientations "
      "unless other stand tilts are given.");
  DocumentTable table;
  table.header = {"sensor set", "combinations", "upright alone", "at the orientations"};
  for (std::size_t s = 0; s < c.chosen.size(); ++s)
    table.rows.push_back({sensorSetName(c.chosen[s].set), std::to_string(c.chosen[s].combinations),
                          scoreText(c.upright[s]), scoreText(c.chosen[s])});
  table.caption =
      "Combinations determined by the design's rows (the rank rule: 1e-8 of the most excited) "
      "and the unit-column condition number where every one is; the structural combinations are "
      "a suspended robot's.";
  doc.table(table);
}

std::string standSummary(const StandDesign& stand) {
  std::ostringstream out;
  out << "  stand orientations (roll, pitch) [rad]: " << tiltsText(stand) << "\n";
  for (std::size_t s = 0; s < stand.choice.chosen.size(); ++s)
    out << "    " << sensorSetName(stand.choice.chosen[s].set) << ": "
        << scoreText(stand.choice.chosen[s]) << " (upright alone "
        << scoreText(stand.choice.upright[s]) << ")\n";
  return out.str();
}

}  // namespace dynid
