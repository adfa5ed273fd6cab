// What `dynid study` writes: study.json (every method's torque fit and GC error, training and
// held out), report.md and a self-contained report.html with the comparison table, what to
// conclude and a figure of torque error against GC error; and the console table.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/studies/log_study.hpp"
#include "reports/document.hpp"

namespace dynid {

nlohmann::json logStudyJson(const LogStudyOutcome& outcome);
/// The comparison as fixed-width text, one row per model.
std::string logStudyTable(const LogStudyOutcome& outcome);
/// Sentences computed from the table: the best model for torques and for motion, held out, and
/// whether they are the same.
std::vector<std::string> logStudyConclusions(const LogStudyOutcome& outcome);
Document logStudyDocument(const LogStudyOutcome& outcome);
/// Writes study.json, report.md, report.html and the figure; returns the console text (the table,
/// the conclusions and the files).
std::string writeLogStudy(const std::string& dir, const LogStudyOutcome& outcome);

}  // namespace dynid
