// The runs wing's room for dynid identifiability and dynid identify: the structural base
// parameters and how a dataset excites them; the least-squares, physically consistent and combined
// estimates, each through the estimation wing's MethodRunner, with the fit's statistics, the
// held-out validation and the write-back. Nothing here prints or writes a report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/estimation/front.hpp"
#include "analysis/estimation/methods.hpp"
#include "analysis/estimation/pipeline.hpp"
#include "analysis/estimation/reversals.hpp"
#include "analysis/estimation/streaming.hpp"
#include "analysis/estimation/training_rows.hpp"
#include "analysis/logs/rest.hpp"
#include "analysis/records/prepare_record.hpp"
#include "analysis/records/summary_record.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/parameters.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/physically_consistent.hpp"

namespace dynid {

struct DataExcitation {
  std::string file;
  int samples = 0;
  Excitation excitation;
  double condition_number = 0.0;  // of the unit-column base regressor
};

struct IdentifiabilityOutcome {
  BaseParameters base;
  StructuralOptions structural;
  double condition_number = 0.0;  // of the unit-column base regressor on fresh random states
  Eigen::VectorXd model_beta;     // the model's own base parameters
  std::optional<DataExcitation> data;
};
/// The structural base parameters of `model`, and, when `data_file` is not empty, how that
/// dataset excites them (streamed on `threads` threads, 0: all; the same result for any count).
/// `data`, when given, holds that dataset in memory (`data_file` then only names it).
IdentifiabilityOutcome identifiabilityRun(const Model& model, const StructuralOptions& structural,
                                          const std::string& data_file = "",
                                          int threads = kAllThreads,
                                          const Trajectory* data = nullptr);

// ---- identification ----

struct IdentifyRequest {
  Model model;
  Method method = Method::kOls;  // ols, wls, pc or combined
  std::optional<Model> prior;    // pc, combined: the prior (default: the model's own parameters)
  double prior_weight = kDefaultPriorWeight;  // pc, combined: > 0 (PhysicalOptions::prior_weight)
  /// combined: its GC segments (normalised by default) and its weight and budgets.
  SegmentOptions segments = normalisedSegments();
  CombinedOptions combined;
  /// combined: the front (analysis/estimation/front.hpp) at these GC weights instead of
  /// combined.gc_weight alone, each point from the last, measured on the held-out data (required)
  /// and the estimate chosen from it by chooseByHeldOut with front_tolerance: the estimate a study
  /// with the same `front_weights` chooses among the front's points. Empty: no front.
  std::vector<double> front_weights;
  double front_tolerance = 0.05;
  std::string data_file;
  std::string validate_file;  // empty: no held-out validation
  /// With validate_file: prepare --keep-raw-torque's validate_raw.csv, the held-out part's raw
  /// torques at the log's stamps, to compare the prediction against too (empty: none).
  std::string validate_raw_file = "";
  /// Data in memory instead of the files (the Python module's arrays); the file names then only
  /// name them in messages and records. Not owned; they must outlive the call.
  const Trajectory* data = nullptr;
  const Trajectory* validate = nullptr;
  StructuralOptions structural;
  /// The URDF the model was loaded from, to write the estimate back into (empty: no write-back).
  std::string write_back_from;
  std::string robot_spec;     // how the robot was named (--robot), recorded for `dynid predict`
  int threads = kAllThreads;  // for the streamed passes over the data (0: all cores)
  /// The joints' rest velocities (analysis/logs/rest.hpp): one for all, or one per joint; empty:
  /// measured on the training data. The estimate, its fit and held-out prediction, and the
  /// combined estimator's rollouts all use them.
  std::vector<double> rest_velocity;
  /// The estimate's covariance (analysis/estimation/covariance.hpp): hac, robust over batches of
  /// samples (a second pass over the training data) or white (one pass).
  CovariancePolicy covariance = CovariancePolicy::kHac;
  /// The low-pass the training torque went through, whose effect on the friction columns the fit
  /// reproduces (identifiability/rows/fit_rows.hpp): std::nullopt, the prepare.json beside
  /// data_file says (none without one); an order of 0, none; otherwise its order and cutoff (its
  /// rate is the data's).
  TorqueFilterChoice torque_filter;
  /// A least-squares summary of the training logs (dynid summarize; runs/summarize.hpp) instead of
  /// data_file: the same estimate (ols, wls, pc) as their samples give, its hac covariance over
  /// the summary's batches; no figures of the training fit (a summary holds no samples), and no
  /// combined (its rollouts need them). `model` must be the summary's robot. Not owned.
  const Summary* summary = nullptr;
  std::string summary_name;  // names it in messages and records

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid identify's options). identifyRun checks its request first.
  void check() const;
};
/// The estimate written back into the robot's own files (data/urdf_writeback.hpp).
struct WriteBack {
  std::string urdf;           // the input URDF carrying the estimate
  std::string model_json;     // the identified model as dynid JSON, every drive term included
  int unseen_directions = 0;  // standard-parameter directions the data cannot see (from the prior)
  /// The estimate's non-zero drive parameters URDF has no place for (Ia, Fo, Fa, Fs), as "Ia3"
  /// with its value and unit: the written URDF goes without them, the JSON carries them.
  std::vector<std::string> not_in_urdf;
};
/// `identified` written into a copy of the URDF `urdf_file` (the robot it was loaded from) and as
/// dynid JSON; `unseen_directions` the standard-parameter directions its data could not see.
/// ParseError for an unreadable URDF. (identify's write-back; study's chosen estimate.)
WriteBack estimateWriteBack(const std::string& urdf_file, const Model& identified,
                            int unseen_directions);
/// The combined estimate's two criteria, train and held out, against pc's.
struct CombinedSummary {
  CombinedResult detail;
  int train_segments = 0, test_segments = 0;           // test: 0 without held-out data
  double gc_train_pc = 0.0, gc_train = 0.0;            // GC errors (normalised by default)
  double gc_test_pc = 0.0, gc_test = 0.0;              // NaN without held-out data
  double torque_train_pc = 0.0, torque_test_pc = 0.0;  // pc's relative torque errors
};
/// A point of identify's front: its weight, its errors on the training and held-out data.
struct IdentifyFrontPoint {
  double weight = 0.0;
  double torque_train = 0.0, gc_train = 0.0;
  HeldOutErrors test;
  int iterations = 0;
  double seconds = 0.0;
  std::string note;  // how it ended (combinedNote)
};
struct IdentifyFront {
  std::vector<IdentifyFrontPoint> points;
  double tolerance = 0.0;
  FrontChoice choice;  // indices into points; the estimate is points[choice.index]
};
struct IdentifyOutcome {
  Method method = Method::kOls;
  BaseParameters base;
  LeastSquaresOutcome result;
  double prior_weight = kDefaultPriorWeight;
  std::vector<std::string> pc_inconsistent_links;  // names of the links OLS lifted inconsistently
  Eigen::VectorXd model_beta;                      // the model's own base parameters
  std::string data_file;
  std::optional<Validation> validation;
  std::string validate_file;
  /// Against the raw held-out torques (validate_raw_file), and how many were not bracketed.
  std::optional<Validation> raw_validation;
  std::string validate_raw_file;
  int raw_skipped = 0;
  std::optional<WriteBack> write_back;      // when requested
  std::optional<CombinedSummary> combined;  // method combined
  std::optional<IdentifyFront> front;       // with front_weights
  /// The robot file's SHA-256 when robot_spec names a file (empty for a built-in robot or data
  /// in memory's model): estimate.json records it beside the model it embeds.
  std::string robot_sha256;
  std::string robot_spec;
  /// Each joint's rest velocity, measured on the training data (or given), and its samples at rest.
  std::vector<RestVelocity> rest;
  // For the report:
  Prediction fit;  // the estimate's torques on the training data
  /// Where the training residual lies in velocity: the joints whose residual gathers near zero
  /// velocity, where friction sticks and breaks away (analysis/estimation/reversals.hpp).
  ReversalResidual reversals;
  std::optional<Prediction> validate_fit;        // and on the held-out data
  std::vector<ConsistencyViolation> violations;  // of the standard estimate, per link
  /// prepare.json when the training data is a `dynid prepare` output (train.csv or validate.csv
  /// beside it): how the log was cleaned, filtered and differentiated.
  PreparationFound preparation;
  /// The rows the fit took (identifiability/rows/fit_rows.hpp): the torque's filter it reproduced
  /// (inactive: none), where that came from, and its reach [samples].
  TorqueFilter torque_filter;
  std::string torque_filter_source;
  int filter_reach = 0;
  /// From a summary: the logs it holds (their files, digests, samples, rest velocities, filters).
  std::vector<SummarySource> summary_sources;
};
/// Throws InputError for a prior of another layout, or, with write_back_from, for an estimate
/// that is not physically consistent (suggesting pc); ParseError for a bad dataset or URDF.
IdentifyOutcome identifyRun(const IdentifyRequest& request);

}  // namespace dynid
