// The documents of `dynid identifiability` (identifiability.json, identifiability.md) and
// `dynid identify` (estimate.json, and the report: report.md, report.html and its figures), and
// their console lines.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/runs/identify.hpp"
#include "reports/document.hpp"

namespace dynid {

/// identifiability.json: the base parameters (names, expressions, coefficients, the model's
/// values), the parameters that never act, the regrouped ones, the null space, the rank gap and
/// conditioning, and with data, how it excites each base parameter.
nlohmann::json identifiabilityJson(const Model& model, const IdentifiabilityOutcome& outcome);
/// identifiability.md: the same findings, for people (rendered from the outcome, as the JSON is).
std::string identifiabilityMarkdown(const Model& model, const IdentifiabilityOutcome& outcome);
/// "puma560: 60 standard parameters, 36 base parameters (rank gap ...), ..." and the files.
std::string identifiabilitySummary(const Model& model, const IdentifiabilityOutcome& outcome,
                                   const std::string& dir);

/// estimate.json: the base estimates with %sigma, the full standard vector, residuals, and the
/// physically consistent solver's record (pc) and the held-out validation when present.
nlohmann::json estimateJson(const Model& model, const IdentifyOutcome& outcome);
/// "puma560: ols estimate of 36 base parameters from N samples, ..." and the files.
/// One line on how the estimate's intervals were computed: the covariance policy, its batch
/// length, the residuals' correlation that chose it and the widening over the white covariance.
std::string covarianceLine(const CovarianceSummary& covariance);
/// One line on the rows the fit took: those left out at rest per joint, and the torque filter
/// whose effect on the friction columns it reproduced; empty when every row was taken unchanged.
std::string fitRowsLine(const IdentifyOutcome& outcome);
/// What a note on the residual at reversals says of the torque's filter: that the fit reproduced
/// it (so the residual is not its artefact), or, for data without a prepare.json, that the
/// request's `torque_filter` makes the fit reproduce a filter it went through (the front ends
/// respell the field); empty otherwise.
std::string filteringClause(const IdentifyOutcome& outcome);

std::string estimateSummary(const Model& model, const IdentifyOutcome& outcome,
                            const std::string& dir);

/// The identification report: the torque fit on training and held-out data (table and figures:
/// measured against predicted torques, residuals against time, their histograms), the
/// preprocessing when the data came from `dynid prepare`, the base parameters with estimates,
/// %sigma and excitation, both condition numbers, each link's physical-consistency verdict, and
/// what the data cannot determine. Figures gnuplot could not draw are named in `missing_figures`.
Document identificationDocument(const Model& model, const IdentifyOutcome& outcome,
                                std::vector<std::string>* missing_figures = nullptr);
/// Writes estimate.json, report.md, report.html and the figures (NAME.svg) into `dir`; returns
/// the console summary (with a warning line when gnuplot did not run).
std::string writeIdentification(const std::string& dir, const Model& model,
                                const IdentifyOutcome& outcome);

/// A warning when a solver stopped at its iteration cap or failed (empty otherwise).
std::string solverWarning(const IdentifyOutcome& outcome);

/// Where the write-back's dynid JSON goes beside `urdf_path`: out.urdf -> out.dynid.json.
std::string writeBackJsonPath(const std::string& urdf_path);
/// Writes the write-back's URDF to `urdf_path` and its JSON beside it, each atomically, both or
/// neither. Returns the console line that says what was written. Throws Error naming the path.
/// A parent directory that does not exist yet is made (and removed again if the write fails).
std::string writeWriteBack(const std::string& urdf_path, const WriteBack& back);

}  // namespace dynid
