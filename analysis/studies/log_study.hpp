// The paper's comparison on the user's own log (`dynid study`): every estimation method, least
// squares (ols, wls, pc) and the GC-error searches (nlo, ga, hybrid) with their refinements, run
// on a real dataset and measured side by side on the two things a user wants from a model: how
// well it fits the measured torques (the relative error ||tau - tau_hat|| / ||tau||) and how well
// it predicts the motion (the GC error: states rolled out over short horizons from the recorded
// states with the recorded torques), each on the training data and on held-out data. There is
// no truth: which estimate to trust for simulation is exactly what the table answers.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/estimation/methods.hpp"
#include "analysis/estimation/pipeline.hpp"
#include "analysis/estimation/reversals.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/identify.hpp"
#include "search/gc_error.hpp"

namespace dynid {

struct LogStudyRequest {
  Model robot;             // its parameters: the user's model (CAD, datasheet, published)
  std::string robot_spec;  // how it was named
  std::string data_file, validate_file;  // dataset CSVs (dynid prepare's train.csv, validate.csv)
  std::vector<Method> methods;           // empty: every method, in allMethods() order
  /// The GC error's; num_segments capped at what each dataset holds. Normalised by default: raw
  /// errors in q [rad] and dq [rad/s] rank a model by how much it damps the fast joints'
  /// velocities rather than by how well it predicts the whole state.
  SegmentOptions segments = normalisedSegments();
  double search_seconds = 30.0;  // per search (0: no time limit)
  long search_evaluations = 0;   // per search (0: no limit); one of the two must be set
  int refine_iterations = 50;    // per refinement stage
  double refine_seconds = 60.0;  // per refinement (0: no limit)
  /// A refinement stops when an iteration lowers the cost by less than this fraction.
  double refine_tolerance = 1e-6;
  bool keep_if_better = true;  // keep a search's result that its refinement did not improve
  double prior_weight =
      kDefaultPriorWeight;  // pc (and so the searches' start): PhysicalOptions::prior_weight
  /// combined: the GC term's weight relative to the torque term's (CombinedOptions::gc_weight);
  /// its iterations, seconds and tolerance are the refinements'.
  double combined_weight = 1.0;
  /// The front (analysis/estimation/front.hpp): the combined estimator at these GC weights (> 0,
  /// increasing; empty: no front), each point with the refinements' budgets, then measured as a
  /// method is.
  std::vector<double> front_weights;
  /// The choice (studyChoice): the least held-out GC error among the physically consistent
  /// estimates whose held-out torque error is within (1 + front_tolerance) of the best of them.
  double front_tolerance = 0.05;
  std::uint64_t seed = 1;
  int threads = kAllThreads;  // 0: every core
  /// The URDF `robot` was loaded from, to write the chosen estimate into (a copy; empty: none).
  /// Needs front_weights.
  std::string write_back_from;
  RunControl control;

  /// Throws InputError when a dataset is missing, no search budget is set or a numeric field is
  /// out of its range (core/option_ranges.hpp, as dynid study's options, by field name).
  /// logStudyRun checks its request first.
  void check() const;
};

/// One model measured on both datasets.
struct LogStudyRow {
  std::string key;  // "model" (the robot's own parameters), "start" (the searches' start: the pc
                    // estimate; only when a search runs), or a method name
  double torque_train = 0.0, torque_test = 0.0;  // relative torque errors
  double gc_train = 0.0, gc_test = 0.0;          // GC errors
  /// The held-out GC error the torque noise alone causes with this model (gcNoiseFloor): the GC
  /// error within kAtNoiseFloor of it says nothing of the model (analysis/estimation/front.hpp).
  double gc_floor_test = 0.0;
  bool consistent = false;  // every link physically consistent
  long evaluations = 0;     // GC evaluations (searches), iterations (refinements, pc)
  double seconds = 0.0;
  std::string note;          // e.g. "stopped at its time budget"
  bool moved = true;         // refinements and combined: false when the result is where it started
  Eigen::VectorXd standard;  // the model's standard parameters (the robot's layout)
};

/// A point of the front, measured as a method's row is (its key "front", its evaluations the
/// combined estimator's iterations, its note how it ended).
struct FrontRow {
  double weight = 0.0;
  LogStudyRow row;
};

struct LogStudyOutcome {
  std::string robot_spec, data_file, validate_file;
  Model model;         // the robot studied (nominal parameters), as study.json embeds it
  ModelSource source;  // and where it came from
  /// The settings an identify of the recommended method repeats: the drive terms ("ia,fv,fc",
  /// "none"), the segments, the pc prior's weight and the combined estimator's (the refinements'
  /// budgets).
  std::string drive_terms;
  SegmentOptions segments;
  double prior_weight = 0.0, combined_weight = 0.0, refine_seconds = 0.0;
  int refine_iterations = 0;
  int train_samples = 0, test_samples = 0;
  int num_base = 0, num_standard = 0;
  int train_segments = 0, test_segments = 0;
  double horizon = 0.0;
  std::vector<LogStudyRow> rows;  // "model", "start", then each method in the request's order
  std::vector<FrontRow> front;    // in weight order; empty when none was asked for
  double front_tolerance = 0.0;   // the request's
  /// Where the first least-squares estimate's (ols, wls or pc, as run) training residual lies
  /// and whether it has the shape of friction (analysis/estimation/reversals.hpp); samples 0 when
  /// none ran.
  ReversalResidual fit_reversals;
  /// The chosen estimate (studyChoice) written into the URDF, with write_back_from.
  std::optional<WriteBack> write_back;
  bool interrupted = false;
  double seconds = 0.0;
};

/// What the study recommends, by rules that cannot contradict each other: a recommendation is
/// only ever a physically consistent row (the input model included, the searches' "start" not:
/// it is pc), and only one with finite held-out errors. Keys; empty when no row qualifies.
struct StudyVerdict {
  std::string simulation;            // the lowest held-out GC error among the consistent rows
  std::string control;               // the lowest held-out torque error among the consistent rows
  std::string best_torque, best_gc;  // the same over every row, consistent or not
  /// One consistent row wins both (simulation == control).
  bool oneForBoth() const { return !simulation.empty() && simulation == control; }
};
StudyVerdict studyVerdict(const std::vector<LogStudyRow>& rows);

/// One estimate chosen by a stated rule on the held-out data (chooseByHeldOut,
/// analysis/estimation/front.hpp): among the physically consistent estimates with finite held-out
/// errors (the rows but the searches' "start", which is pc, and the front's points) whose held-out
/// torque error is at most (1 + tolerance) times the least of theirs, the least held-out GC error
/// above its noise floor; at the floor, the least torque error. The input model is a candidate as
/// any other: where it predicts the motion best within the bound, it is chosen. Ties go to the
/// earlier (the rows in order, then the front by weight).
struct StudyChoice {
  std::string key;            // a row's key, or "front"; empty when no estimate qualifies
  int front_index = -1;       // the front's point (key "front")
  double torque_bound = 0.0;  // (1 + tolerance) x the best consistent held-out torque error
  std::string best_torque;    // the estimate whose torque error sets the bound (or "front")
  int best_front_index = -1;  // the front's point that sets it
  bool at_floor = false;      // the chosen one's held-out GC error is at its noise floor
};
StudyChoice studyChoice(const LogStudyOutcome& outcome, double tolerance);
/// The row (or front point) `choice` names; nullptr when none.
const LogStudyRow* studyChosenRow(const LogStudyOutcome& outcome, const StudyChoice& choice);

/// Throws InputError for an invalid setting (named), a dataset of another joint count, a held-out
/// file that is missing (validate_file is required), data too short for one GC segment; ParseError
/// for a malformed dataset; NumericalError when the data do not excite every base parameter.
LogStudyOutcome logStudyRun(const LogStudyRequest& request);

}  // namespace dynid
