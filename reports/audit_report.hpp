// What `dynid audit` writes: audit.json (every base parameter's estimates per session, its
// chi-square test and flag, the totals, each session's share and the verdict) and report.md /
// report.html (the verdict, the flagged parameters by group, the sessions, the full table).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/studies/audit.hpp"

namespace dynid {

nlohmann::json auditJson(const AuditOutcome& outcome);
/// Writes audit.json and the report into `dir` as one set. Returns the console summary.
std::string writeAudit(const std::string& dir, const AuditOutcome& outcome);

}  // namespace dynid
