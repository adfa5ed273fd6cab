// The runs wing's room for dynid search and dynid refine: the GC-error searches (nlo, ga, hybrid)
// with their checkpoints, and the Ceres refinement of a search's or an estimate's result, each
// through the estimation wing's dispatch. Nothing here prints or writes a report.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/estimation/methods.hpp"
#include "analysis/records/model_source.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/run_control.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "search/gc_error.hpp"
#include "search/optimizers.hpp"
#include "search/parameter_space.hpp"
#include "search/refinement/refine.hpp"

namespace dynid {

struct SearchRequest {
  Model robot;
  ModelSource robot_source;       // where `robot` came from (search.json embeds both)
  Method method = Method::kNlo;   // nlo, ga or hybrid
  std::optional<Model> init;      // initial estimate (default: the robot's parameters)
  std::optional<double> perturb;  // or: the robot's parameters perturbed by up to this fraction
  std::optional<Model> truth;     // for parameter errors
  std::string data_file, validate_file;
  const Trajectory* data = nullptr;      // data in memory instead of data_file (not owned)
  SpaceOptions space;                    // total_mass and total_mass_constraint resolved below
  std::string mass_constraint = "auto";  // on, off or auto (on for nlo and hybrid)
  std::optional<double> total_mass;      // default: the truth's, else the initial estimate's
  SegmentOptions segments;               // segments.seed is set from `seed`
  SearchBudget budget;                   // all zero: 60 s
  NloOptions nlo;
  GaOptions ga;
  std::uint64_t seed = 1;
  int threads = kAllThreads;  // 0: all cores
  std::string checkpoint;     // saved after every round or generation; resumed when it exists
  RunControl control;
  std::function<void(const SearchState&)> on_iteration;  // progress (after the checkpoint)

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid search's options). searchRun checks its request first.
  void check() const;
};

struct SearchOutcome {
  std::string robot;
  Model model;         // the request's robot (nominal parameters), as search.json embeds it
  ModelSource source;  // and where it came from
  Method method = Method::kNlo;
  nlohmann::json settings;  // search.json's "settings" (analysis/records/search_record.hpp)
  std::shared_ptr<const ParameterSpace> space;
  SearchResult result;
  std::optional<double> initial_parameter_error, final_parameter_error;  // with a truth
  std::string validate_file;
  double validate_initial_gc = 0.0, validate_final_gc = 0.0;  // with a validate file
};
/// Runs the search. Throws InputError for models of another structure, a checkpoint written with
/// other settings or invalid options, ParseError for bad files.
SearchOutcome searchRun(const SearchRequest& request);

// ---- refinement ----

struct RefineRequest {
  Model robot;
  ModelSource robot_source;  // where `robot` came from (refine.json embeds both)
  std::string from_file;     // a search.json (dynid search) or an estimate.json (dynid identify)
  std::optional<nlohmann::json> from_document;  // that document in memory (from_file names it)
  std::string data_file, validate_file;
  const Trajectory* data = nullptr;  // data in memory instead of data_file (not owned)
  std::optional<Model> truth;
  RefineOptions options;  // num_threads 0: all cores; stop from `control`
  // For a start from estimate.json: the space and segments (a search.json carries its own).
  ParameterForm form = ParameterForm::kPaper;
  double range = 0.5;
  double horizon = 0.05;
  int segments = 100;
  RunControl control;

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid refine's options). refineRun checks its request first.
  void check() const;
};

struct RefineOutcome {
  std::string robot;
  Model model;         // the request's robot (nominal parameters), as refine.json embeds it
  ModelSource source;  // and where it came from
  std::string from_file, from_kind;  // "search" or "estimate"
  std::string data_file;
  std::shared_ptr<const ParameterSpace> space;
  SegmentOptions segment_options;
  int num_segments = 0;
  RefineOptions options;
  RefineResult result;
  BaseParameters base;
  Eigen::VectorXd x0, beta0;              // the start, in free and base coordinates
  std::optional<double> rms_start_shift;  // estimated starts' RMS shift from the measured ones
  // With a truth:
  bool has_truth = false;
  double initial_parameter_error = 0.0, final_parameter_error = 0.0;
  double initial_base_error = 0.0, final_base_error = 0.0, final_base_error_max = 0.0;
  std::optional<double> base_stage_base_error;
  // With a validate file:
  std::string validate_file;
  double validate_initial_gc = 0.0, validate_final_gc = 0.0;
  std::vector<std::string> warnings;  // a start of an earlier version read as it is
};
/// Throws ParseError for a start file that is neither document (or lacks a field), InputError for
/// a truth of another layout or invalid options.
RefineOutcome refineRun(const RefineRequest& request);

/// A held-out dataset's GC problem, read and checked before a long run (its refusals, such as too
/// few samples for the segments, name the file then, not after the run's budget is spent).
GcProblem heldOutProblem(const std::string& file, int num_joints, const SegmentOptions& segments);
/// The GC errors of two models on a held-out problem: (first, second).
std::pair<double, double> heldOutGc(const Model& first, const Model& second, const GcProblem& test,
                                    int threads);

}  // namespace dynid
