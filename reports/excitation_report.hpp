// What `dynid excite` writes: excitation.json (the design, the limits used, every criterion for
// the design and for the default sinusoid, the expected standard deviation of every base
// parameter), excitation.csv (t, q, dq, ddq at a chosen rate, to stream to a controller), and a
// report (Markdown and HTML) with the joint trajectories against their limits.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/excitation/excite.hpp"
#include "analysis/records/model_source.hpp"
#include "reports/document.hpp"
#include "reports/stand_tilts_report.hpp"

namespace dynid {

/// The settings the design was made with, as excitation.json records them.
struct ExcitationSettings {
  std::string robot;  // the --robot spec
  int harmonics = 0, starts = 0, evaluations = 0;
  double period = 0.0;
  double csv_rate = 1000.0;  // samples per second of excitation.csv [Hz]
  ModelSource source;  // where the robot came from (excitation.json embeds it, with the model)
  /// The stand orientations chosen for the design (`--stands`); unset: none (`stand` null).
  std::optional<StandDesign> stand;
};

nlohmann::json excitationJson(const Model& model, const ExcitationSettings& settings,
                              const ExciteOutcome& outcome);
/// t, q1..qn, dq1..dqn, ddq1..ddqn at `rate` over one period (header line first).
std::string excitationCsv(const Model& model, const FourierSeries& design, double rate);
/// The report; figures need gnuplot (their names go to `missing_figures` when it does not run).
Document excitationDocument(const Model& model, const ExcitationSettings& settings,
                            const ExciteOutcome& outcome,
                            std::vector<std::string>* missing_figures);
/// Writes excitation.json, excitation.csv, report.md, report.html and the figures into `dir`,
/// each atomically. Returns the console summary.
std::string writeExcitation(const std::string& dir, const Model& model,
                            const ExcitationSettings& settings, const ExciteOutcome& outcome);

}  // namespace dynid
