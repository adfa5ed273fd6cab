// The run records' JSON: the one module that writes and reads search.json's settings and
// estimates, the search checkpoint, the start a refinement reads (search.json or estimate.json)
// and a comparison row. Errors in a file read here are ParseErrors naming the file and the JSON
// path of the field, as data/model_json's are. reports/ assembles the documents from these pieces;
// analysis/ reads them back.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/comparison.hpp"
#include "core/model.hpp"
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
/// The checkpoint document of a search state (schema_version 1, kind dynid.search_checkpoint).
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

/// What a refinement starts from, read from a search.json or an estimate.json.
struct RefineStart {
  std::string kind;  // "search" or "estimate"
  SpaceOptions space;
  SegmentOptions segments;
  Model initial, estimate;  // the space's initial model and the start
};
/// Reads `document` (the contents of `file`). For a search.json, the space and segments are the
/// search's and exactly its free parameters are freed; for an estimate.json, `space` and
/// `segments` are used as given. Every standard parameter of `robot`'s layout must be present.
/// Throws ParseError naming the file and field.
RefineStart refineStartFrom(const nlohmann::json& document, const std::string& file,
                            const Model& robot, const SpaceOptions& space,
                            const SegmentOptions& segments);

/// estimate.json's schema_version (written by reports/identification_report).
inline constexpr int kEstimateSchemaVersion = 1;

/// What predict and refine read from an `identify` estimate.json.
struct EstimateRecord {
  std::string robot_spec;                  // "" when the estimate does not say
  std::string method;                      // "" when absent
  std::vector<std::string> drive_terms;    // keys: "fv", "fc", ...
  std::map<std::string, double> standard;  // standard_estimate.values
  nlohmann::json kinematics;               // the recorded kinematics signature, or null
};
/// Reads an estimate.json document strictly: schema_version exactly kEstimateSchemaVersion,
/// unknown top-level keys refused, robot_spec a string, drive_terms an array of names,
/// standard_estimate {note, values} with every value a finite number within
/// +-kMaxParameterMagnitude, kinematics an array of 15-entry rows. Throws ParseError naming `file`
/// and the field.
EstimateRecord estimateRecordFrom(const nlohmann::json& document, const std::string& file);
/// The standard vector in the order of `names` (a robot's layout). Throws ParseError naming the
/// first missing or extra parameter ("standard_estimate.values.Ixx3") and saying the estimate was
/// made for another robot (or edited) when the names differ.
Eigen::VectorXd standardVectorFrom(const EstimateRecord& record,
                                   const std::vector<std::string>& names, const std::string& file,
                                   const std::string& robot_spec);

/// A comparison row: {gc_error_initial, gc_error_train, gc_error_test, torque_rms_test,
/// param_error, base_param_error, evaluations, seconds}; non-finite numbers are null.
nlohmann::json metricsJson(const MethodMetrics& m);

/// Parses `text` as JSON; throws ParseError naming `file` ("invalid JSON: ...").
nlohmann::json parseJson(const std::string& text, const std::string& file);

}  // namespace dynid
