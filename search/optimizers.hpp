// The paper's GC-error searches (section III): multistart COBYLA (NLO), the genetic algorithm with
// migration (GA), and GA followed by NLO from the GA's best (hybrid, the paper's future work).
//
// Every candidate is projected onto the feasible set (bounds, and the total mass when that
// constraint is on) before its GC error is computed, so every evaluated candidate satisfies the
// constraints; COBYLA also carries the total mass as an equality constraint and a penalty on its
// distance to the feasible point it was evaluated at.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"

namespace dynid {

struct SearchBudget {
  long max_evaluations = 0;   // 0: unlimited
  double max_seconds = 0.0;   // 0: unlimited (wall time)
  double gc_tolerance = 0.0;  // stop when the best GC error is at or below this
};

/// One round (NLO) or generation (GA).
struct HistoryEntry {
  std::string stage;  // "nlo" or "ga"
  int iteration = 0;
  double best_gc = 0.0;
  double best_parameter_error = std::numeric_limits<double>::quiet_NaN();  // of the best-GC member
  double min_parameter_error = std::numeric_limits<double>::quiet_NaN();   // smallest present
  long evaluations = 0;
  double seconds = 0.0;
};

struct NloOptions {
  int evaluations_per_seed = 400;  // COBYLA budget for each of the three seeds of a round
  double mutation_scale = 0.1;     // seeds 2 and 3: each parameter times (1 + N(0, scale))
  double initial_step = 0.1;       // COBYLA's initial step, as a fraction of each range
};

struct GaOptions {
  int population = 100;
  double crossover_rate = 0.7;  // else the child copies its first parent
  double mutation_rate = 0.1;   // per parameter
  double mutation_scale = 0.1;  // sigma = scale * |current value|
  double migration = 0.05;      // after each generation x <- c + (1 + migration)(x - c)
  int elites = 1;               // best individuals copied unchanged into the next generation
};

/// What a search can resume from (written to --checkpoint after every round or generation).
struct SearchState {
  std::string method;  // "nlo", "ga" or "hybrid"
  std::string stage;   // the stage running when saved
  int iteration = 0;
  std::string rng;  // std::mt19937_64 state
  Eigen::VectorXd best_x;
  double best_gc = std::numeric_limits<double>::infinity();
  double initial_gc = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::VectorXd> population;  // GA
  std::vector<double> population_gc;
  long evaluations = 0;
  double seconds = 0.0;
  std::vector<HistoryEntry> history;
};

struct SearchResult {
  std::string method;
  std::string termination;  // "tolerance", "evaluations", "seconds", "interrupted"
  Eigen::VectorXd best_x;   // free parameters (ParameterSpace), feasible
  double initial_gc = 0.0;
  double best_gc = 0.0;
  long evaluations = 0;
  double seconds = 0.0;
  std::vector<HistoryEntry> history;
  /// (GC error, parameter error) of every evaluated candidate, when the truth is known.
  std::vector<std::pair<double, double>> evaluated;
};

/// Everything a search needs besides its options.
struct SearchContext {
  const ParameterSpace* space = nullptr;
  const GcProblem* problem = nullptr;
  ThreadPool* pool = nullptr;
  const Eigen::VectorXd* truth_full = nullptr;  // the form's full true vector, or null
  SearchBudget budget;
  std::uint64_t seed = 1;
  RunControl control = {};  // stop flag (stops after this evaluation), deadline, progress
  std::function<void(const SearchState&)> on_iteration;               // progress and checkpoints
  std::function<void(const Eigen::VectorXd&, double)> on_evaluation;  // every candidate, its GC
  const SearchState* resume = nullptr;                                // continue a checkpointed run
};

/// Runs the chosen method from the space's initial estimate. Throws InputError for invalid
/// options (population < 2, negative rates, ...).
SearchResult runNlo(const SearchContext& context, const NloOptions& options);
SearchResult runGa(const SearchContext& context, const GaOptions& options);
/// GA for half of each budget (evaluations and seconds), then NLO from the GA's best.
SearchResult runHybrid(const SearchContext& context, const GaOptions& ga, const NloOptions& nlo);

}  // namespace dynid
