#include "reports/audit_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
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
                          {"flagged", p.flagged},
                          {"farthest_session", p.farthest + 1}});
  return {{"schema_version", kAuditDocument.schema_version},
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
          {"parameters", parameters},
          {"warnings", o.warnings}};
}

namespace {
std::string headline(const AuditOutcome& o) {
  std::ostringstream s;
  s << o.sessions.size() << " sessions of " << o.robot << " (" << o.method << "), "
    << o.parameters.size() << " base parameters: " << o.verdict << ". " << o.flagged
    << " flagged at the " << formatNumber(100.0 * o.level, 3) << " % level (" << o.flagged_inertial
    << " inertial, " << o.flagged_friction << " friction); overall chi2 " << formatNumber(o.chi2, 4)
    << " on " << o.dof << " degrees of freedom, p = " << formatNumber(o.p_value, 3) << ".";
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
      {"How sure", "chi2 " + formatNumber(o.chi2, 4) + " on " + std::to_string(o.dof) +
                       " degrees of freedom, p = " + formatNumber(o.p_value, 3) + " (level " +
                       formatNumber(100.0 * o.level, 3) + " %)"},
      {"Moved", moved.empty() ? "nothing flagged" : moved},
      {"Next", o.flagged == 0 || o.sessions.empty()
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
  table.header = {"parameter", "group", "weighted mean", "chi2", "p", "flagged", "farthest"};
  for (const AuditParameter& p : o.parameters)
    table.rows.push_back({p.name, p.group, formatNumber(p.mean, 5), formatNumber(p.chi2, 3),
                          formatNumber(p.p_value, 2), p.flagged ? "yes" : "",
                          std::to_string(p.farthest + 1)});
  table.caption =
      "Per base parameter, chi2 = sum over sessions of ((estimate - mean) / sigma)^2 with the "
      "inverse-variance weighted mean, on sessions - 1 degrees of freedom; flagged when its "
      "p-value is below the level. Farthest: the session farthest from the mean in its own sigmas.";
  report.table(table);
  OutputSet set(dir);
  set.add("audit.json", jsonText(auditJson(o), 2) + "\n");
  set.add("report.md", report.markdown());
  set.add("report.html", report.html());
  set.publish();
  return headline(o) + "\nwrote " + dir + "/audit.json, report.md, report.html\n";
}

}  // namespace dynid
