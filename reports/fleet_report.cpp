#include "reports/fleet_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "data/model_json.hpp"
#include "reports/document.hpp"
#include "reports/output.hpp"
#include "reports/summary_report.hpp"

namespace dynid {

using nlohmann::json;

namespace {

bool isFrictionName(const std::string& name) {
  for (const char* prefix : {"Fv", "Fc", "Fa", "Fs", "Fo"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

json robotJson(const FleetOutcome& o, const FleetRobot& r) {
  json logs = json::array();
  for (const SummarySource& s : r.sources) logs.push_back(summarySourceJson(s));
  json outside = json::array();
  for (int k : r.verdict.outside_parameters)
    outside.push_back(
        {{"name", o.base_names[static_cast<std::size_t>(k)]}, {"z", numberOrNull(r.verdict.z[k])}});
  const int far = r.verdict.farthest;
  return {{"name", r.name},
          {"logs", logs},
          {"samples", r.samples},
          {"outside", r.verdict.outside},
          {"learnt_from", r.verdict.learnt_from},
          {"inflation", numberOrNull(r.inflation)},
          {"farthest",
           {{"name", o.base_names[static_cast<std::size_t>(far)]},
            {"z", numberOrNull(r.verdict.z[far])},
            {"p_value", numberOrNull(r.verdict.p_value[far])}}},
          {"outside_parameters", outside},
          {"estimate", numbersOrNull(r.alone.beta)},
          {"std_dev", numbersOrNull(r.alone.std_dev)},
          {"posterior", numbersOrNull(r.verdict.posterior)},
          {"posterior_std", numbersOrNull(r.verdict.posterior_std)},
          {"z", numbersOrNull(r.verdict.z)},
          {"p_value", numbersOrNull(r.verdict.p_value)},
          {"relative_error", numberOrNull(r.alone.relative_error)}};
}

}  // namespace

json fleetJson(const FleetOutcome& o) {
  json parameters = json::array();
  for (std::size_t k = 0; k < o.base_names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    json outside = json::array();
    for (const FleetRobot& r : o.robots)
      if (r.verdict.p_value[i] < o.prior.test_level) outside.push_back(r.name);
    parameters.push_back({{"name", o.base_names[k]},
                          {"expression", o.base_expressions[k]},
                          {"group", isFrictionName(o.base_names[k]) ? "friction" : "inertial"},
                          {"model", numberOrNull(o.model_beta[i])},
                          {"mean", numberOrNull(o.prior.mean[i])},
                          {"spread", numberOrNull(o.prior.spread[i])},
                          {"spread_upper", numberOrNull(o.prior.spread_upper[i])},
                          {"mean_std", numberOrNull(o.prior.mean_std[i])},
                          {"robots_outside", outside}});
  }
  json robots = json::array();
  for (const FleetRobot& r : o.robots) robots.push_back(robotJson(o, r));
  json out = documentHeader(kFleetDocument);
  out["robot"] = o.robot_spec;
  out["model"] = json::parse(modelToJson(o.model));
  out["model_source"] = modelSourceJson(o.model_source);
  out["method"] = methodName(o.method);
  out["covariance"] = covariancePolicyName(o.covariance);
  out["flag_level"] = o.options.flag_level;
  out["test_level"] = numberOrNull(o.prior.test_level);
  out["z_threshold"] = numberOrNull(o.prior.z_threshold);
  out["rounds"] = o.prior.rounds;
  out["converged"] = o.prior.converged;
  out["learnt_from"] = o.prior.learnt_from;
  out["verdict"] = o.verdict;
  out["interrupted"] = o.interrupted;
  out["parameters"] = parameters;
  out["robots"] = robots;
  out["warnings"] = o.warnings;
  return out;
}

namespace {

std::string headline(const FleetOutcome& o) {
  std::ostringstream s;
  s << o.robots.size() << " robots of " << o.robot_spec << " (" << methodName(o.method) << ", "
    << o.base_names.size() << " base parameters): " << o.verdict << ". The prior was learnt from "
    << o.prior.learnt_from << " robots in " << o.prior.rounds
    << (o.prior.rounds == 1 ? " round" : " rounds") << "; a robot lies outside when a parameter's "
    << "|z| against the fleet without it (its spread at the upper end of its 95 % interval) "
    << "exceeds " << formatNumber(o.prior.z_threshold, 3) << " (p below "
    << formatNumber(o.prior.test_level, 3) << "; a "
    << formatNumber(100.0 * o.options.flag_level, 3)
    << " % chance that a fleet of robots alike has one flagged).";
  return s.str();
}

std::vector<std::pair<std::string, std::string>> verdictBox(const FleetOutcome& o) {
  std::string outside;
  for (const FleetRobot& r : o.robots) {
    if (!r.verdict.outside) continue;
    std::string params;
    int listed = 0;
    for (int k : r.verdict.outside_parameters)
      if (listed++ < 4)
        params += (params.empty() ? "" : ", ") + o.base_names[static_cast<std::size_t>(k)] +
                  " (z " + formatNumber(r.verdict.z[k], 3) + ")";
    const std::size_t more = r.verdict.outside_parameters.size();
    if (more > 4) params += " and " + std::to_string(more - 4) + " more";
    outside += (outside.empty() ? "" : "; ") + r.name + ": " + params;
  }
  return {{"Compared", std::to_string(o.robots.size()) + " robots of " + o.robot_spec + " (" +
                           methodName(o.method) + ", " + std::to_string(o.base_names.size()) +
                           " base parameters)"},
          {"Verdict", o.verdict},
          {"How sure",
           "each parameter against the fleet without the robot, its spread at the "
           "upper end of its 95 % interval: |z| beyond " +
               formatNumber(o.prior.z_threshold, 3) + " (p below " +
               formatNumber(o.prior.test_level, 3) + "): a " +
               formatNumber(100.0 * o.options.flag_level, 3) +
               " % chance of one false flag in the fleet (Bonferroni over robots x "
               "parameters)"},
          {"Outside", outside.empty() ? "no robot" : outside},
          {"Next", outside.empty()
                       ? "the fleet's posterior estimates (fleet.json, posterior) are each "
                         "robot's best: its own data where they are sure, the fleet's where not"
                       : "look at the robots outside for a changed tool, payload or part (inertial "
                         "parameters), worn or cold drives (friction), or "
                         "another model; they keep their own estimates"}};
}

DocumentTable robotsTable(const FleetOutcome& o) {
  DocumentTable t;
  t.header = {"robot", "logs", "samples", "outside", "farthest", "z", "p", "sigma widened"};
  for (const FleetRobot& r : o.robots) {
    const int k = r.verdict.farthest;
    t.rows.push_back({r.name, std::to_string(r.sources.size()), std::to_string(r.samples),
                      r.verdict.outside ? "yes" : "", o.base_names[static_cast<std::size_t>(k)],
                      formatNumber(r.verdict.z[k], 3), formatNumber(r.verdict.p_value[k], 2),
                      formatNumber(r.inflation, 3)});
  }
  t.caption =
      "Each robot's parameter farthest from the fleet without it (the smallest p), in sigma of "
      "the difference (its own variance, the fleet's spread and the fleet mean's variance), and "
      "its two-sided p, the fleet's spread taken at the upper end of its 95 % interval (learnt "
      "from a few robots, it may be larger than they show); sigma widened: the "
      "robust covariance's median inflation over the white one, applied to its covariance.";
  return t;
}

DocumentTable parametersTable(const FleetOutcome& o) {
  DocumentTable t;
  t.header = {"parameter", "group", "model", "fleet mean", "spread", "spread %", "robots outside"};
  for (std::size_t k = 0; k < o.base_names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    int outside = 0;
    for (const FleetRobot& r : o.robots)
      outside += r.verdict.p_value[i] < o.prior.test_level ? 1 : 0;
    t.rows.push_back({o.base_names[k], isFrictionName(o.base_names[k]) ? "friction" : "inertial",
                      formatNumber(o.model_beta[i], 4), formatNumber(o.prior.mean[i], 5),
                      formatNumber(o.prior.spread[i], 3),
                      percentText(o.prior.spread[i] / std::abs(o.prior.mean[i])),
                      outside ? std::to_string(outside) : ""});
  }
  t.caption =
      "The prior learnt from the robots inside the fleet (empirical Bayes, docs/FLEET.md): the "
      "weighted mean and the robots' spread about it beyond their own sigma (Paule-Mandel; 0 "
      "when they agree within their sigma).";
  return t;
}

}  // namespace

std::string writeFleet(const std::string& dir, const FleetOutcome& o) {
  Document report("Fleet: " + o.robot_spec);
  report.verdict(verdictBox(o));
  report.paragraph(headline(o));
  report.bullets(o.warnings);
  report.heading("Robots");
  report.table(robotsTable(o));
  report.heading("The fleet's prior");
  report.table(parametersTable(o));
  OutputSet set(dir);
  set.add("fleet.json", jsonText(withProvenance(fleetJson(o)), 2) + "\n");
  set.add("report.md", report.markdown());
  set.add("report.html", report.html());
  set.publish();
  return headline(o) + "\nwrote " + dir + "/fleet.json, report.md, report.html\n";
}

}  // namespace dynid
