// search.json's records (its settings, history and estimate) and the search checkpoint: written
// by reports/run_report (search.json) and the search run (the checkpoint), read back here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "search/gc_error.hpp"
#include "search/optimizers.hpp"
#include "search/parameter_space.hpp"

namespace dynid {

/// search.json's "settings": everything that rebuilds the search's space and segments, and the
/// options that decided its course.
struct SearchSettingsRecord {
  SpaceOptions space;  // `fixed` is not written: free_parameters says it
  std::vector<std::string> free_parameters;
  SegmentOptions segments;  // num_segments and step as resolved by makeGcProblem
  std::uint64_t seed = 1;
  SearchBudget budget;
  GaOptions ga;
  NloOptions nlo;
  std::string data;  // the training dataset's path
};
nlohmann::json searchSettingsJson(const SearchSettingsRecord& settings);

/// The settings a checkpoint must share with the run that resumes it: all but the budgets and the
/// tolerance, which only decide when to stop (so a run can be resumed with a larger budget).
nlohmann::json checkpointFingerprint(nlohmann::json settings);
/// The checkpoint document of a search state (kCheckpointDocument).
nlohmann::json checkpointJson(const SearchState& state, const nlohmann::json& settings);
/// What a checkpoint must match to resume a run: its method, the number of free parameters and
/// the GA population (empty / -1 / 0: not checked).
struct CheckpointShape {
  std::string method;
  long dimension = -1;
  long population = 0;
};
/// The state in a checkpoint document. Throws ParseError naming `file` and the field when a field
/// is missing, of the wrong type, out of range (negative counts, a corrupt generator state), of
/// the wrong size for `shape`, or unknown.
SearchState checkpointFrom(const nlohmann::json& document, const std::string& file,
                           const CheckpointShape& shape = {});

/// The per-round (NLO) or per-generation (GA) history.
nlohmann::json historyJson(const std::vector<HistoryEntry>& history);

/// The estimate at free parameters x in the paper (7 per link) and standard (10) forms, keyed by
/// parameter name: {"paper": {...}, "standard": {...}}.
nlohmann::json estimateJson(const ParameterSpace& space, const Eigen::VectorXd& x);

/// The checkpoint at `path` when it exists: its state, after checking that it was written by a
/// search of `method` with these settings (searchSettingsJson's; budgets may differ). Throws
/// ParseError naming the file and the field otherwise.
std::optional<SearchState> readCheckpoint(const std::string& path, const nlohmann::json& settings,
                                          const std::string& method);

}  // namespace dynid
