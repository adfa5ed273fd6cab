#include "reports/standing_design_report.hpp"

#include <cmath>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"

namespace dynid {

namespace {

const char* kSwayForm =
    "c_i(t) = offset_i + sum_k a_ik / (k w) sin(k w t) - b_ik / (k w) cos(k w t), w = 2 pi / "
    "period, for x, y, z [m] (world axes, from where the stance puts the base) and roll, pitch, "
    "yaw [rad] (R = Rz(yaw) Ry(pitch) Rx(roll)); at rest at the stance at t = 0 and after each "
    "period";

const char* kSwayCriterion =
    "the unit-column condition number of the set's base regressor over the sway, in the "
    "standing class (the base parameters that random sways of this stance, and the design, "
    "excite together, by identify's rank rule)";

nlohmann::json coefficientRows(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) row.push_back(m(i, k));
    out.push_back(row);
  }
  return out;
}

nlohmann::json swayScoreJson(const StandingSetScore& s) {
  return {{"determined", s.determined}, {"condition", numberOrNull(s.condition)}};
}

/// "90 of 94, condition 1.27e+05" or "87 of 94".
std::string swayScoreText(const StandingSetScore& s) {
  return std::to_string(s.determined) + " of " + std::to_string(s.holding) +
         (std::isfinite(s.condition) ? ", condition " + formatNumber(s.condition, 3) : "");
}

std::string feetText(const std::vector<std::string>& contacts) {
  std::string out;
  for (std::size_t k = 0; k < contacts.size(); ++k) out += (k ? "," : "") + contacts[k];
  return out;
}

/// The bounds and how near the design comes to each.
std::string swayBoundsText(const StandingDesignRequest& r, const StandingDesign& d) {
  std::string out = "sway " + formatNumber(d.largest_sway, 3) + " m of " +
                    formatNumber(r.max_sway, 3) + ", turn " + formatNumber(d.largest_turn, 3) +
                    " rad of " + formatNumber(r.max_turn, 3) + ", the joints at least " +
                    formatNumber(d.joint_clearance, 3) + " rad from a limit (margin " +
                    formatNumber(r.joint_margin, 3) + ")";
  if (r.friction_cone > 0.0)
    out += ", the feet's forces within " + formatNumber(100.0 * d.cone_use, 3) +
           " % of cones of mu " + formatNumber(r.friction_cone, 3);
  else
    out += ", no friction cone imposed";
  if (d.joints)
    out += ", the joints no foot depends on within " + formatNumber(d.largest_swing, 3) +
           " rad of the stance (of " + formatNumber(r.max_swing, 3) + ")";
  if (!r.sole.empty())
    out += ", every centre of pressure at least " + formatNumber(d.sole_clearance, 3) +
           " m inside its sole";
  return out;
}

}  // namespace

nlohmann::json standingDesignJson(const StandingDesignRequest& request,
                                  const StandingDesign& design,
                                  const StandingDesignSource& source) {
  nlohmann::json out = documentHeader(kStandingExcitationDocument);
  out["robot"] = source.robot;
  out["model_source"] = modelSourceJson(modelSourceOf(source.robot));
  out["contacts"] = source.contacts;
  out["stance"] =
      std::vector<double>(request.stance.data(), request.stance.data() + request.stance.size());
  out["set"] = sensorSetName(request.set);
  out["design"] = {
      {"period", design.base.period},
      {"harmonics", design.base.harmonics()},
      {"coordinates", {"x", "y", "z", "roll", "pitch", "yaw"}},
      {"offset", std::vector<double>(design.base.offset.data(), design.base.offset.data() + 6)},
      {"a", coefficientRows(design.base.a)},
      {"b", coefficientRows(design.base.b)},
      {"form", kSwayForm}};
  nlohmann::json sole = nlohmann::json::array();
  for (const Eigen::Vector2d& corner : request.sole) sole.push_back({corner.x(), corner.y()});
  if (design.joints) {
    const FourierSeries& j = *design.joints;
    out["joint_design"] = {
        {"period", j.period},
        {"harmonics", j.harmonics()},
        {"offset", std::vector<double>(j.offset.data(), j.offset.data() + j.offset.size())},
        {"a", coefficientRows(j.a)},
        {"b", coefficientRows(j.b)},
        {"form",
         "q_j(t) as `design`'s form, for the joints no foot depends on (the "
         "rows of the others are zero and unread: the feet set them)"}};
  } else {
    out["joint_design"] = nullptr;
  }
  out["limits"] = {{"max_sway", request.max_sway},           {"max_turn", request.max_turn},
                   {"max_swing", request.max_swing},         {"joint_margin", request.joint_margin},
                   {"friction_cone", request.friction_cone}, {"sole", sole}};
  out["designed"] = {{"largest_sway", design.largest_sway},
                     {"largest_turn", design.largest_turn},
                     {"joint_clearance", design.joint_clearance},
                     {"cone_use", design.cone_use},
                     {"largest_swing", design.largest_swing},
                     {"sole_clearance", numberOrNull(design.sole_clearance)},
                     {"shrink", design.shrink}};
  nlohmann::json sets = nlohmann::json::array();
  for (std::size_t s = 0; s < design.scores.size(); ++s) {
    const StandingSetScore& d = design.scores[s];
    sets.push_back({{"set", sensorSetName(d.set)},
                    {"holding", d.holding},
                    {"standing", d.standing},
                    {"design", swayScoreJson(d)},
                    {"default_sway", design.baseline.empty() ? nlohmann::json(nullptr)
                                                             : swayScoreJson(design.baseline[s])}});
  }
  out["sets"] = sets;
  out["criterion"] = kSwayCriterion;
  out["default_sway_problem"] = design.baseline_problem.empty()
                                    ? nlohmann::json(nullptr)
                                    : nlohmann::json(design.baseline_problem);
  nlohmann::json starts = nlohmann::json::array();
  for (double v : design.start_objectives)
    starts.push_back(std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(std::pow(10.0, v)));
  out["optimiser"] = {
      {"method", "COBYLA (NLopt), multistart"}, {"starts", starts},
      {"best_start", design.best_start},        {"evaluations_per_start", request.evaluations},
      {"evaluations", design.evaluations},      {"grid_rate", request.grid_rate},
      {"check_rate", request.check_rate},       {"seed", request.seed},
      {"termination", design.termination},      {"seconds", design.seconds}};
  return out;
}

std::string standingDesignMarkdown(const StandingDesignRequest& request,
                                   const StandingDesign& design,
                                   const StandingDesignSource& source) {
  Document doc("A standing sway for " + source.robot);
  const StandingSetScore* chosen = nullptr;
  for (const StandingSetScore& s : design.scores)
    if (s.set == request.set) chosen = &s;
  doc.verdict({{"Designed", std::string("the base's six coordinates over ") +
                                formatNumber(design.base.period, 4) + " s, for " +
                                sensorSetName(request.set) +
                                (chosen ? ": " + swayScoreText(*chosen) : std::string())},
               {"Within", swayBoundsText(request, design)},
               {"Next",
                "run the sway on the robot, or simulate the robot along it "
                "(standing_excitation.json is its trajectory), then identify the data it "
                "gives"}});
  doc.heading("What each sensor set determines");
  DocumentTable table;
  table.header = {"set", "holding states", "any sway of this stance", "this design",
                  "the default sway"};
  for (std::size_t s = 0; s < design.scores.size(); ++s) {
    const StandingSetScore& d = design.scores[s];
    table.rows.push_back(
        {sensorSetName(d.set), std::to_string(d.holding), std::to_string(d.standing),
         swayScoreText(d),
         design.baseline.empty() ? "cannot be followed" : swayScoreText(design.baseline[s])});
  }
  table.caption =
      "Base parameters determined (and the unit-column condition number where the motion "
      "determines all a sway can). Four feet fixed in the world tie the legs' motion to the "
      "base's: a sway can determine fewer than holding states do.";
  doc.table(table);
  if (!design.baseline_problem.empty())
    doc.paragraph("The default sway (the one dynid generates over a stance): " +
                  design.baseline_problem);
  doc.heading("How it was designed");
  doc.paragraph(std::string("Criterion: ") + kSwayCriterion + ". COBYLA from " +
                std::to_string(design.start_objectives.size()) + " seeded starts (seed " +
                std::to_string(request.seed) + "), " + std::to_string(design.evaluations) +
                " evaluations on a " + formatNumber(request.grid_rate, 3) +
                " Hz grid, checked at " + formatNumber(request.check_rate, 3) + " Hz" +
                (design.shrink < 1.0 ? " (scaled by " + formatNumber(design.shrink, 3) +
                                           " to keep the bounds between the grid's samples)"
                                     : std::string()) +
                "; ended by its " +
                (design.termination == "evaluations" ? std::string("evaluations")
                 : design.termination == "seconds"   ? std::string("time budget")
                                                     : std::string("interruption (Ctrl-C)")) +
                ". Contacts: " + feetText(source.contacts) + ".");
  return doc.markdown();
}

std::string standingDesignSummary(const StandingDesignRequest& request,
                                  const StandingDesign& design, const std::string& dir) {
  std::ostringstream out;
  out << "a standing sway over " << formatNumber(design.base.period, 4) << " s for "
      << sensorSetName(request.set) << " (" << design.evaluations << " evaluations in "
      << formatNumber(design.seconds, 3) << " s"
      << (design.termination == "seconds"       ? ", stopped by the time budget"
          : design.termination == "interrupted" ? ", interrupted: the best sway so far"
                                                : "")
      << ")\n";
  for (std::size_t s = 0; s < design.scores.size(); ++s) {
    const StandingSetScore& d = design.scores[s];
    out << "  " << sensorSetName(d.set) << ": " << swayScoreText(d)
        << " (any sway of this stance: " << d.standing << ")";
    if (!design.baseline.empty()) out << "; the default sway " << swayScoreText(design.baseline[s]);
    out << "\n";
  }
  if (!design.baseline_problem.empty())
    out << "  the default sway: " << design.baseline_problem << "\n";
  out << "  within the bounds: " << swayBoundsText(request, design) << "\n";
  out << "  wrote " << dir << "/standing_excitation.json and standing_excitation.md\n";
  return out.str();
}

}  // namespace dynid
