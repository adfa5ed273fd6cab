// The one hallway: every pipeline a command runs is wired here, once, and used alike by the CLI,
// by Study (the demo) and by batch runs. A run takes a request (models already loaded, settings
// validated at the boundary by its caller), reads the datasets it names, and returns an outcome
// that reports/ turns into documents. Nothing here prints or writes a report.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/methods.hpp"
#include "analysis/pipeline.hpp"
#include "analysis/records/prepare_record.hpp"
#include "analysis/reversals.hpp"
#include "analysis/streaming.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/parameters.hpp"
#include "core/simulate.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/physically_consistent.hpp"
#include "search/optimizers.hpp"
#include "search/refinement/refine.hpp"

namespace dynid {

// ---- models and dynamics ----

/// Each link frame in the base frame at q = 0, to compare with a datasheet's drawing.
std::vector<Pose<double>> linkFramesAtZero(const Model& model);
/// The kinematics an estimate's parameters refer to: per link its frame at q = 0 (rotation
/// row-major, then origin) and its joint axis in the base frame at q = 0, 15 numbers per link.
/// Estimates record it, and `predict` refuses a robot whose kinematics differ.
Eigen::MatrixXd kinematicsSignature(const Model& model);

/// Every physical-consistency violation of the model's links (empty: all consistent).
std::vector<ConsistencyViolation> consistencyViolations(const Model& model);

/// The dynamics at one state: tau = RNEA(q, dq, ddq), or ddq = ABA(q, dq, tau) when `tau` is
/// given; M = CRBA(q) either way.
struct DynamicsOutcome {
  Eigen::VectorXd q, dq, ddq, tau;
  Eigen::MatrixXd M;
};
/// q, dq and the given one of ddq, tau have n entries (InputError otherwise). Throws
/// NumericalError when the dynamics are singular at the state (a massless moving subtree).
DynamicsOutcome dynamicsAt(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                           const std::optional<Eigen::VectorXd>& ddq,
                           const std::optional<Eigen::VectorXd>& tau);

// ---- simulation ----

struct SimulateRequest {
  Model robot;                            // the simulated truth
  std::optional<Model> controller_model;  // the controller's model (default: the robot)
  double controller_perturb = 0.0;        // its parameters perturbed by up to this fraction
  bool fourier = false;                   // seeded Fourier series instead of sinusoids
  std::string trajectory;                 // or: the design in this excitation.json (`dynid excite`)
  /// With a trajectory: simulation.duration is replaced by the design's period (one period, the
  /// motion the design was made for; the CLI sets this when --duration is not given).
  bool one_period = false;
  std::optional<Eigen::VectorXd> q0;  // centre [rad] (default: the middle of the limits)
  Eigen::VectorXd amplitude;          // n entries [rad]
  std::optional<Eigen::VectorXd> frequency, phase;  // sinusoidal [Hz], [rad]
  double base_frequency = 0.1;                      // fourier [Hz]
  int harmonics = 5;                                // fourier, >= 1
  std::optional<Eigen::VectorXd> kp, kd, tau_max;   // default gains and effort limits otherwise
  double bandwidth = 5.0;                           // for the default gains [Hz]
  SimulationOptions simulation;
  std::vector<Disturbance> disturbances;  // external pushes, recorded in SimulateOutcome::external

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid simulate's options). simulateRun checks its request first.
  void check() const;
};
struct SimulateOutcome {
  Trajectory trajectory;
  double tracking_rms = 0.0;  // RMS of q - q_desired over samples and joints [rad]
  double peak_torque = 0.0;   // max |tau| [N m]
  /// The largest torque change between two recorded samples, over joints [N m], and the share of
  /// samples at which some joint's torque is at its limit.
  double max_torque_step = 0.0, saturated_share = 0.0;
  /// The default gains' rule: "mass-matrix diagonal" (the paper's, kp_i = M_ii w^2) or
  /// "effective inertia" (1 / (M^-1)_ii, when the diagonal's would put a closed-loop mode above
  /// 3 times the bandwidth); "given" with --kp or --kd.
  std::string gains_rule;
  /// With disturbances: the external joint torque at every sample (n x samples) [N m].
  Eigen::MatrixXd external;
};
/// Simulates the robot under a tracking controller. Throws InputError for a controller model of
/// another joint count or harmonics < 1, ParseError for a bad `trajectory` file, and what
/// simulate() throws.
SimulateOutcome simulateRun(const SimulateRequest& request);

/// Seeded Fourier coefficients, scaled so each joint's excursion bound sum (|a|+|b|)/(w k) equals
/// its amplitude.
FourierSeries randomFourier(const Eigen::VectorXd& q0, const Eigen::VectorXd& amplitude,
                            double base_frequency, int harmonics, std::uint64_t seed);

// ---- identifiability ----

/// How well a dataset excites the base parameters.
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
/// The combined estimate's two criteria, train and held out, against pc's.
struct CombinedSummary {
  CombinedResult detail;
  int train_segments = 0, test_segments = 0;           // test: 0 without held-out data
  double gc_train_pc = 0.0, gc_train = 0.0;            // GC errors (normalised by default)
  double gc_test_pc = 0.0, gc_test = 0.0;              // NaN without held-out data
  double torque_train_pc = 0.0, torque_test_pc = 0.0;  // pc's relative torque errors
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
  std::string robot_spec;
  // For the report:
  Prediction fit;  // the estimate's torques on the training data
  /// Where the training residual lies in velocity: the joints whose residual gathers near zero
  /// velocity, where friction sticks and breaks away (analysis/reversals.hpp).
  ReversalResidual reversals;
  std::optional<Prediction> validate_fit;        // and on the held-out data
  std::vector<ConsistencyViolation> violations;  // of the standard estimate, per link
  /// prepare.json when the training data is a `dynid prepare` output (train.csv or validate.csv
  /// beside it): how the log was cleaned, filtered and differentiated.
  PreparationFound preparation;
};
/// Throws InputError for a prior of another layout, or, with write_back_from, for an estimate
/// that is not physically consistent (suggesting pc); ParseError for a bad dataset or URDF.
IdentifyOutcome identifyRun(const IdentifyRequest& request);

// ---- applying an estimate to data ----

struct PredictRequest {
  std::string estimate_file;  // an identify estimate.json (empty: `model`)
  std::string data_file;      // a dataset CSV
  std::string robot_spec;     // empty: the estimate's own; with `model`, its spec
  /// Without an estimate: this robot with its own parameters (a URDF, a written-back model, a
  /// built-in), which has no covariance and so no band.
  std::optional<Model> model;
  int threads = kAllThreads;       // 0: all cores; the same result for any count
  PredictionSink* sink = nullptr;  // receives every sample's prediction, in order (may be null)
  /// prepare --keep-raw-torque's validate_raw.csv for data_file: the raw torques at the log's
  /// stamps, compared against too (empty: none).
  std::string raw_file = "";
};
struct PredictOutcome {
  Model model;  // the robot with the estimate's standard parameters
  std::string robot_spec, method;
  Prediction prediction;
  std::optional<PredictionBand> band;  // the estimate's 95 % band (absent in older estimates)
  std::optional<Validation> raw;       // against the raw torques (raw_file), when given
  ReversalResidual reversals;          // where the residual lies in velocity (reversals.hpp)
  std::string raw_file;
  int raw_skipped = 0;  // raw samples no two adjacent dataset samples bracket
};
/// The robot an identify estimate.json names (or `robot_spec`), with the estimate's drive terms and
/// standard parameters; `spec_used` and `method` (when given) receive the robot spec used and the
/// estimate's method. Throws ParseError for a malformed estimate, InputError when it does not fit
/// the robot (another robot, another drive model: the parameter named).
/// `band`, when given, receives the estimate's prediction band (its base covariance and joint
/// noise; nothing for an estimate written before dynid recorded them).
Model estimateModel(const std::string& file, const std::string& robot_spec,
                    std::string* spec_used = nullptr, std::string* method = nullptr,
                    std::optional<PredictionBand>* band = nullptr);
/// Loads the robot the estimate names (or `robot_spec`) with the estimate's drive terms, sets its
/// standard parameters and predicts, streaming the dataset. Throws ParseError for a malformed
/// estimate, InputError when the estimate does not fit the robot (another robot, another drive
/// model: the parameter named).
PredictOutcome predictRun(const PredictRequest& request);

/// The arm given as an identify estimate.json (its robot loaded, or `robot_spec` when given, with
/// the estimate's parameters) or as a robot spec (loadRobot with `drive_terms`). Throws as
/// loadRobot and estimateModel; InputError for --robot or drive terms given where they do not
/// apply.
struct LoadedArm {
  Model model;
  std::string robot_spec;      // the robot's spec (the estimate's, or `arm` itself)
  bool from_estimate = false;  // the parameters came from an estimate.json
  /// The estimate's torque source: the torque constants and gear ratios its motor currents were
  /// converted with (empty: its torques were not currents, or the arm is no estimate).
  std::vector<double> torque_constants, gear_ratios;
};
LoadedArm loadArm(const std::string& arm, const std::string& robot_spec,
                  const std::optional<DriveTerms>& drive_terms, std::vector<std::string>* warnings);

// ---- the GC-error searches ----

struct SearchRequest {
  Model robot;
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
  std::string from_file;  // a search.json (dynid search) or an estimate.json (dynid identify)
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

/// `threads`, or every core for 0.
int resolveThreads(int threads);

}  // namespace dynid
