#include "reports/audit_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"
#include "reports/output.hpp"

namespace dynid {

using nlohmann::json;

json auditJson(const AuditOutcome& o) {
  json parameters = json::array();
  for (const AuditParameter& p : o.parameters)
    parameters.push_back({{"name", p.name},
                          {"expression", p.expression},
                          {"group", p.group},
                          {"estimate", numbersOrNull(p.estimate)},
                          {"std_dev", numbersOrNull(p.std_dev)},
                          {"mean", numberOrNull(p.mean)},
                          {"chi2", numberOrNull(p.chi2)},
                          {"dof", p.dof},
                          {"p_value", numberOrNull(p.p_value)},
                          {"p_scaled", numberOrNull(p.p_scaled)},
                          {"flagged", p.flagged},
                          {"farthest_session", p.farthest + 1}});
  nlohmann::json out = {
      {"schema_version", kAuditDocument.schema_version},
      {"kind", kAuditDocument.kind},
      {"robot", o.robot},
      {"method", o.method},
      {"sessions", o.sessions},
      {"level", o.level},
      {"verdict", o.verdict},
      {"chi2", numberOrNull(o.chi2)},
      {"dof", o.dof},
      {"p_value", numberOrNull(o.p_value)},
      {"flagged", o.flagged},
      {"flagged_inertial", o.flagged_inertial},
      {"flagged_friction", o.flagged_friction},
      {"session_chi2", numbersOrNull(o.session_chi2)},
      {"covariance_policies", o.covariance_policies},
      {"dispersion",
       {{"median_chi2_ratio", numberOrNull(o.dispersion)},
        {"above_median", numberOrNull(o.above_median)},
        {"sign_p_value", numberOrNull(o.sign_p_value)},
        {"sigma_too_small", o.sigma_too_small},
        {"sigma_scale", numberOrNull(o.sigma_scale)},
        {"note",
         "the sigma are too small alike when more than half of the parameters' chi-squares lie "
         "above their median (sign test, p < 0.01) and the median chi-square is at least 1.5 "
         "times its expectation (10 parameters or more); parameters are then flagged by the "
         "test with every sigma times sigma_scale (p_scaled)"}}},
      {"parameters", parameters},
      {"warnings", o.warnings}};
  // The robot audited (the first session's; sessions share it), as estimates embed it.
  if (!o.model.is_null()) out["model"] = o.model;
  out["model_source"] = modelSourceJson(o.source);
  return out;
}

namespace {
std::string headline(const AuditOutcome& o) {
  std::ostringstream s;
  s << o.sessions.size() << " sessions of " << o.robot << " (" << o.method << "), "
    << o.parameters.size() << " base parameters: " << o.verdict << ". " << o.flagged
    << " flagged at the " << formatNumber(100.0 * o.level, 3) << " % level (" << o.flagged_inertial
    << " inertial, " << o.flagged_friction << " friction); overall chi2 " << formatNumber(o.chi2, 4)
    << " on " << o.dof << " degrees of freedom, p = " << formatNumber(o.p_value, 3)
    << (o.sigma_too_small ? " (sigma scaled)" : "") << ".";
  if (o.sigma_too_small)
    s << " The sigma are too small alike: " << formatNumber(100.0 * o.above_median, 3)
      << " % of the parameters' chi-squares lie above their median (sign test p = "
      << formatNumber(o.sign_p_value, 2) << "), the median is " << formatNumber(o.dispersion, 3)
      << " times its expectation; flags and p are with every sigma times "
      << formatNumber(o.sigma_scale, 3) << ".";
  return s.str();
}
/// The report's verdict box: what was compared, whether it holds, what moved, what next.
std::vector<std::pair<std::string, std::string>> verdictBox(const AuditOutcome& o) {
  std::string moved;
  int listed = 0;
  for (const AuditParameter& p : o.parameters)
    if (p.flagged && listed++ < 5) moved += (moved.empty() ? "" : ", ") + p.name;
  if (o.flagged > 5) moved += " and " + std::to_string(o.flagged - 5) + " more";
  int farthest = 0;
  for (Eigen::Index i = 0; i < o.session_chi2.size(); ++i)
    if (o.session_chi2[i] > o.session_chi2[farthest]) farthest = static_cast<int>(i);
  return {
      {"Compared", std::to_string(o.sessions.size()) + " sessions of " + o.robot + " (" + o.method +
                       "), " + std::to_string(o.parameters.size()) + " base parameters"},
      {"Verdict", o.verdict},
      {"How sure",
       "chi2 " + formatNumber(o.chi2, 4) + " on " + std::to_string(o.dof) +
           " degrees of freedom, p = " + formatNumber(o.p_value, 3) +
           (o.sigma_too_small ? " with every sigma times " + formatNumber(o.sigma_scale, 3)
                              : std::string()) +
           " (level " + formatNumber(100.0 * o.level, 3) + " %)"},
      {"Moved", moved.empty() ? "nothing flagged" : moved},
      {"Next", o.sigma_too_small && o.flagged == 0
                   ? "the model holds no better than its sigma say: multiply them by " +
                         formatNumber(o.sigma_scale, 3) +
                         " (model error the sessions share or correlated residuals), or improve "
                         "the model (friction, drive terms)"
               : o.flagged == 0 || o.sessions.empty()
                   ? "the model holds across these sessions"
                   : "session " + std::to_string(farthest + 1) + " (" + o.sessions[farthest] +
                         ") differs most: re-identify from it, or look for a changed payload, "
                         "warm-up or drive"}};
}
}  // namespace

std::string writeAudit(const std::string& dir, const AuditOutcome& o) {
  Document report("Audit: " + o.robot);
  report.verdict(verdictBox(o));
  report.paragraph(headline(o));
  report.bullets(o.warnings);
  report.heading("Sessions");
  DocumentTable sessions;
  sessions.header = {"session", "file", "chi2 share"};
  for (std::size_t i = 0; i < o.sessions.size(); ++i)
    sessions.rows.push_back({std::to_string(i + 1), o.sessions[i],
                             formatNumber(o.session_chi2[static_cast<Eigen::Index>(i)], 4)});
  sessions.caption =
      "Each session's sum over parameters of ((estimate - weighted mean) / its sigma)^2: the "
      "session that differs most has the largest share (about parameters x (sessions - 1) / "
      "sessions each when they agree).";
  report.table(sessions);
  report.heading("Parameters");
  DocumentTable table;
  table.header = {"parameter",        "group",   "weighted mean", "chi2", "p",
                  "p (sigma scaled)", "flagged", "farthest"};
  for (const AuditParameter& p : o.parameters)
    table.rows.push_back({p.name, p.group, formatNumber(p.mean, 5), formatNumber(p.chi2, 3),
                          formatNumber(p.p_value, 2), formatNumber(p.p_scaled, 2),
                          p.flagged ? "yes" : "", std::to_string(p.farthest + 1)});
  table.caption =
      "Per base parameter, chi2 = sum over sessions of ((estimate - mean) / sigma)^2 with the "
      "inverse-variance weighted mean, on sessions - 1 degrees of freedom; flagged when its "
      "p-value (with every sigma times the sigma scale when the sigma are too small alike) is "
      "below "
      "the level. Farthest: the session farthest from the mean in its own sigmas.";
  report.table(table);
  OutputSet set(dir);
  set.add("audit.json", jsonText(withProvenance(auditJson(o)), 2) + "\n");
  set.add("report.md", report.markdown());
  set.add("report.html", report.html());
  set.publish();
  return headline(o) + "\nwrote " + dir + "/audit.json, report.md, report.html\n";
}

}  // namespace dynid
