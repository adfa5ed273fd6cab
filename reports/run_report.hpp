// The documents of `dynid search` (search.json) and `dynid refine` (refine.json), assembled from
// analysis/records/search_record.hpp's pieces, and their console lines.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/runs/search.hpp"

namespace dynid {

/// search.json (schema_version 1): method, robot, settings, termination, GC errors, the estimate
/// and the initial estimate (paper and standard forms), history and evaluations; with a truth the
/// parameter errors and every evaluated candidate's (GC error, parameter error); with held-out
/// data its GC errors before and after.
nlohmann::json searchJson(const SearchOutcome& outcome);
/// "puma560 nlo: GC error a -> b (...x lower) in N evaluations, T s (termination)" and the file.
std::string searchSummary(const SearchOutcome& outcome, const std::string& dir);
/// The progress line of a search state (for a terminal, ending in "\r" use), with the share of
/// the budget used and the time left when the budget has seconds or evaluations.
std::string searchProgressLine(Method method, const SearchState& state,
                               const SearchBudget& budget = {});

/// refine.json (schema_version 1, kind dynid.refine): settings, both stages, the estimate, the
/// base parameters with their covariance, the free directions, and with a truth or held-out data
/// their errors.
nlohmann::json refineJson(const RefineOutcome& outcome);
/// "puma560 refine: GC error a -> b in ... iterations, T s (termination)" and the file.
std::string refineSummary(const RefineOutcome& outcome, const std::string& dir);
/// A warning when the refinement stopped at its iteration cap or time budget (empty otherwise).
std::string refineWarning(const RefineOutcome& outcome);

}  // namespace dynid
