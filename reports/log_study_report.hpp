// What `dynid study` writes: study.json (every method's torque fit and GC error, training and
// held out), report.md and a self-contained report.html with the comparison table, what to
// conclude and a figure of torque error against GC error; and the console table.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

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
/// The identify run that repeats the study's recommended estimate (the chosen one when a front
/// was swept), as identify's request fields: the report's next step. Only the settings that
/// differ from identify's defaults are set; `write_urdf` for a URDF robot. The library names the
/// fields; the caller (the CLI) spells them as a command line through a RepeatSpelling.
struct StudyRepeat {
  std::string method, robot_spec, drive_terms, data_file, validate_file, out, write_urdf;
  std::optional<double> prior_weight, combined_weight, combined_seconds, horizon;
  std::optional<int> combined_iterations, segments;
  bool raw_gc = false;
  /// A front's point: identify's front (`front_weights`: the study's, empty for the default
  /// sweep; `front_tolerance` when not the default). identify chooses among the front's points
  /// only: `front_differs` when that takes another point than the study's choice (whose bound an
  /// estimate off the front set).
  bool front = false;
  std::vector<double> front_weights;
  std::optional<double> front_tolerance;
  bool front_differs = false;
};
/// The repeat of the recommended estimate; nullopt when it is not identify's (none, the input
/// model, a search).
std::optional<StudyRepeat> studyRepeat(const LogStudyOutcome& outcome);
/// How a caller writes a repeat (the CLI: the dynid identify command). Empty: by field name.
using RepeatSpelling = std::function<std::string(const StudyRepeat&)>;
/// A repeat by identify's request fields ("identify with method = combined, combined_weight = 3,
/// ...").
std::string repeatByFields(const StudyRepeat& repeat);

Document logStudyDocument(const LogStudyOutcome& outcome, const RepeatSpelling& spell = {});
/// Writes study.json, report.md, report.html and the figure; returns the console text (the table,
/// the conclusions and the files).
std::string writeLogStudy(const std::string& dir, const LogStudyOutcome& outcome,
                          const RepeatSpelling& spell = {});

}  // namespace dynid
