// The one estimation pipeline. An EstimationProblem holds what every method needs (base
// parameters, the least-squares source, the training GC problem, the search start and budgets,
// the physically consistent and refinement settings, one run control); a MethodRunner runs any
// Method on it (ols, wls, pc, nlo, ga, hybrid and their refinements) and holds every policy once:
// least-squares dispatch, the search spaces and their start, memoised searches, refinement and
// keep-if-better. identifyRun (dynid identify), searchRun and refineRun, Study (demo, batch) and
// logStudyRun (dynid study) all estimate through it, so they cannot disagree.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "analysis/estimation/covariance.hpp"
#include "analysis/estimation/methods.hpp"
#include "core/parallel.hpp"
#include "core/run_control.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/least_squares_summary.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/physically_consistent.hpp"
#include "search/gc_error.hpp"
#include "search/optimizers.hpp"
#include "search/parameter_space.hpp"
#include "search/refinement/combined.hpp"
#include "search/refinement/refine.hpp"

namespace dynid {

/// One least-squares estimate (ols, wls or pc) of the base parameters.
struct LeastSquaresOutcome {
  BaseEstimate estimate;  // for pc: the base fields of the consistent solution
  std::optional<PhysicalEstimate> pc;
  Eigen::VectorXd standard;      // a full standard vector: pc's, or beta with the rest from `prior`
  CovarianceSummary covariance;  // how estimate.covariance was computed (the problem's policy)
};

/// Where the least-squares rows come from: a dense observation, or a stream's factors (memory
/// independent of the dataset's length). Exactly one is set.
struct LeastSquaresSource {
  const Observation* observation = nullptr;
  LeastSquaresStream* stream = nullptr;  // estimates flush its pending rows
  ParameterLayout layout;                // the stream's parameter layout (pc needs it)
  /// The stream's samples again, in order, for the hac covariance's pass (none: the white
  /// covariance, and the summary says so).
  TrainingReplay replay;
  /// The rows the stream's fit took (identifiability/rows/fit_rows.hpp), for the replay; null:
  /// every row of the model's regressor.
  const FitRows* rows = nullptr;
  /// When the stream holds a summary's rows (LeastSquaresSummary::addTo): the hac covariance from
  /// its batches instead of a replay.
  const LeastSquaresSummary* summary = nullptr;
};

/// The one least-squares dispatch: `method` is ols, wls or pc (InputError otherwise); `prior`
/// (p entries) fills what the data cannot see and is pc's prior.
LeastSquaresOutcome leastSquaresEstimate(Method method, const BaseParameters& base,
                                         const LeastSquaresSource& source,
                                         const Eigen::VectorXd& prior,
                                         const PhysicalOptions& pc_options = {});

/// The combined estimate (search/refinement/combined.hpp) from a pc outcome (`pc`, with its
/// PhysicalEstimate): pc's problem is the torque term and its estimate the start (or `start`, a
/// standard vector inside pc's physical set: a front's previous point). The outcome's standard
/// vector and base fields are the combined estimate's (residuals from `source`; the covariance
/// stays pc's, the torques' alone). Throws InputError when `pc` has no physically consistent
/// estimate, NumericalError when its rollouts diverge.
LeastSquaresOutcome combinedEstimate(const Model& model, const BaseParameters& base,
                                     const LeastSquaresSource& source,
                                     const LeastSquaresOutcome& pc, const GcProblem& gc,
                                     const CombinedOptions& options, CombinedResult* detail,
                                     const Eigen::VectorXd* start = nullptr);

/// One line on how a combined estimate ended: its termination, both criteria from start to end,
/// and "no step was taken" when it stayed at pc's estimate.
std::string combinedNote(const CombinedResult& result);

/// The one search dispatch: runs `method` (nlo, ga or hybrid; InputError otherwise) on a prepared
/// context.
SearchResult dispatchSearch(Method method, const SearchContext& context, const GaOptions& ga,
                            const NloOptions& nlo);

/// How a GC-error refinement runs and whether its result is kept.
struct RefineSettings {
  RefineOptions options;       // every refinement option; threads and stop come from the problem
  bool keep_if_better = true;  // keep the search's result when refinement ends with a higher
                               // training GC error
};

/// The searches' total-mass plane.
enum class MassPlane {
  kAuto,  // NLO and hybrid hold the total mass (the paper's NLO), GA does not
  kOn,
  kOff,
};

/// Where the searches start.
enum class SearchStart {
  kPrior,                 // the problem's start model
  kPhysicallyConsistent,  // the pc estimate (a realisable body whose friction dissipates)
};

struct EstimationProblem {
  Model model;  // the robot: its structure, and the parameters of `prior` unless given
  const BaseParameters* base = nullptr;
  LeastSquaresSource least_squares;
  Eigen::VectorXd prior;  // pc's prior and what least squares cannot see (empty: the model's)
  PhysicalOptions physical;
  /// The least-squares estimates' covariance (ols, wls, pc; combined keeps pc's).
  CovariancePolicy covariance = CovariancePolicy::kHac;
  // Searches and refinements (null when only least squares run):
  const GcProblem* train_gc = nullptr;
  SearchStart search_start = SearchStart::kPrior;
  std::optional<Model> start;  // kPrior's start model (default: the model)
  SpaceOptions space;          // the searches' space; its total-mass fields come from:
  MassPlane mass_plane = MassPlane::kAuto;
  std::optional<double> total_mass;     // the total-mass plane (default: the start's mass)
  const SearchState* resume = nullptr;  // a saved state the (one) search continues from
  SearchBudget search_budget;
  std::uint64_t seed = 1;
  GaOptions ga;
  NloOptions nlo;
  RefineSettings refine;
  CombinedOptions combined;                     // threads and run control come from the problem
  const Eigen::VectorXd* truth_full = nullptr;  // the paper form's true vector (errors), or null
  /// Called after each search iteration with the method, its state and its space.
  std::function<void(Method, const SearchState&, const ParameterSpace&)> on_search_iteration;
  int threads = 1;  // >= 1
  RunControl control;

  /// The budgets study and batch give: each search's seconds and evaluations, and each
  /// refinement's iterations, seconds and tolerance, which the combined estimator shares (its
  /// iterations and seconds; its tolerance stays its own).
  void setBudgets(double search_seconds, long search_evaluations, int refine_iterations,
                  double refine_seconds, double refine_tolerance, bool keep_if_better) {
    search_budget.max_seconds = search_seconds;
    search_budget.max_evaluations = search_evaluations;
    refine.options.max_iterations = combined.max_iterations = refine_iterations;
    refine.options.max_seconds = combined.max_seconds = refine_seconds;
    refine.options.function_tolerance = refine_tolerance;
    refine.keep_if_better = keep_if_better;
  }
};

/// One method's estimate.
struct Estimate {
  Method method = Method::kOls;
  Model model;
  long evaluations = 0;  // GC evaluations (searches), iterations (refinements, pc), 0 (ols, wls)
  double seconds = 0.0;
  std::string note;  // refinements: how it ended, or why the search's result was kept
  /// Refinements and combined: false when the result is where it started (no step kept).
  bool moved = true;
  /// Refinements: the training GC error where the refinement started; NaN otherwise.
  double start_gc = std::numeric_limits<double>::quiet_NaN();
  const LeastSquaresOutcome* least_squares =
      nullptr;  // least-squares methods (owned by the runner)
};

class MethodRunner {
 public:
  /// Throws InputError for threads < 1 or a prior of the wrong size. Base parameters are needed
  /// by least squares and refinements, a least-squares source by least squares (InputError when
  /// a method that needs one runs without it).
  explicit MethodRunner(EstimationProblem problem);
  MethodRunner(const MethodRunner&) = delete;
  MethodRunner& operator=(const MethodRunner&) = delete;

  /// Runs `method`, once: least squares and searches are memoised (a refinement refines its
  /// search's result, searching first when needed). Searches and refinements need train_gc
  /// (InputError otherwise).
  Estimate run(Method method);

  /// The least-squares outcome of `method` (ols, wls, pc), computed on first use.
  const LeastSquaresOutcome& leastSquares(Method method);
  /// How the combined estimate ended (both criteria from start to end) when it has run, else null.
  const CombinedResult* combinedDetail() const {
    return combined_detail_ ? &*combined_detail_ : nullptr;
  }
  /// The search `method` (nlo, ga, hybrid) when it has run, else null.
  const SearchResult* searchResult(Method method) const;
  /// The space the search `method` moves in (the problem's space options; the total-mass plane
  /// by mass_plane), built on first use from the search start.
  const ParameterSpace& space(Method method);
  std::shared_ptr<const ParameterSpace> sharedSpace(Method method);
  /// Refines the point x0 of `space` (an estimate from elsewhere, e.g. `dynid refine` of a
  /// search.json) on the training GC problem with the problem's refine options; the base stage
  /// uses the problem's base parameters when it has them. run() refines its own searches by it.
  /// `uncertainty`: RefineOptions::uncertainty (run() leaves it out: its tables do not use it).
  RefineResult refineFrom(const ParameterSpace& space, const Eigen::VectorXd& x0,
                          bool uncertainty = true);
  /// The searches' start model (kPhysicallyConsistent: computes the pc estimate).
  const Model& searchStart();
  const EstimationProblem& problem() const { return problem_; }
  /// The run control of the runs that follow (SIGINT, a deadline), replacing the problem's.
  void setControl(const RunControl& control) { problem_.control = control; }
  /// The saved state the next search continues from (its space must be this runner's).
  void setResume(const SearchState* state) { problem_.resume = state; }
  ThreadPool& pool() { return pool_; }

 private:
  Model modelWith(const Eigen::VectorXd& theta) const;
  /// The problem's covariance policy on a least-squares outcome (hac: a pass over the
  /// source's rows at the estimate).
  void applyCovariancePolicy(Method method, LeastSquaresOutcome& ls);
  const SearchResult& search(Method method);
  Estimate refine(Method method);
  Estimate combined();
  EstimationProblem problem_;
  ThreadPool pool_;
  GcWorkspace workspace_;
  std::map<Method, std::pair<LeastSquaresOutcome, double>> least_squares_;  // with seconds
  std::map<Method, SearchResult> searches_;
  std::optional<std::pair<LeastSquaresOutcome, double>> combined_;  // with seconds
  std::optional<CombinedResult> combined_detail_;
  std::optional<Model> start_;
  std::shared_ptr<const ParameterSpace> spaces_[2];  // without and with the total-mass plane
};

}  // namespace dynid
