// The main job, `dynid demo`: the paper's study on the built-in PUMA 560 end to end. Simulate
// training and held-out data, find the base parameters, identify them by least squares (OLS, WLS,
// physically consistent), search the GC error (NLO, GA, hybrid), refine the NLO, GA and hybrid
// results, and measure every estimate in the same coordinates (comparison.hpp).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "analysis/studies/comparison.hpp"
#include "analysis/studies/study.hpp"
#include "core/parallel.hpp"
#include "search/optimizers.hpp"

namespace dynid {

struct DemoOptions {
  bool quick = false;           // 4 s of data, 20 segments, 2 s searches (the tests' mode)
  std::uint64_t seed = 1;       // the initial guess's perturbation and the searches
  int threads = kAllThreads;    // 0: all cores
  double search_seconds = 0;    // per search; 0: 30 s (2 s quick), unless evaluations are set
  long search_evaluations = 0;  // per search; 0: no limit (then search_seconds applies)
  int refine_iterations = 0;    // per refinement stage; 0: 200 (30 quick)
  double refine_seconds = 0.0;  // per refinement; 0: no limit
  double prior_weight = kDefaultPriorWeight;  // pc
  bool keep_if_better = true;  // keep a search's result that its refinement did not improve
  RunControl control;  // stop (SIGINT): finish the current stage, skip the rest; progress per stage

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid demo's options, by field name). runDemo checks its options first.
  void check() const;
};

struct DemoIdentifiability {
  int num_standard = 0, num_base = 0;
  std::vector<std::string> base_names, base_expressions;
  std::vector<std::string> unidentifiable;   // standard parameters in no base parameter
  double condition_number = 0.0;             // of the training base regressor, unit columns
  std::vector<double> ols_relative_std_dev;  // %sigma of the OLS estimate, per base parameter
};

/// One search's course (the paper's Figs. 2 and 5) and how its two errors relate.
struct DemoSearchTrace {
  std::string method;                 // nlo, ga, hybrid
  std::vector<HistoryEntry> history;  // per round (NLO) or generation (GA)
  std::vector<double> base_errors;    // the best candidate's base-parameter error, per entry
  long candidates = 0;                // candidates evaluated
  /// (GC error, 7-parameter error) of the evaluated candidates, every k-th so at most 2000.
  std::vector<std::pair<double, double>> evaluated;
  /// Over every evaluated candidate: Pearson's r of log10 GC error and log10 parameter error,
  /// and Spearman's rank correlation (NaN with fewer than 3 candidates).
  double pearson_log = 0.0, spearman = 0.0;
};

struct DemoResult {
  StudySettings settings;  // as run (robot, durations, budgets, seed, threads)
  bool quick = false;
  DemoIdentifiability identifiability;
  std::vector<MethodMetrics> methods;  // in the order ols, wls, pc, nlo, ga, hybrid, refined
  std::vector<DemoSearchTrace> searches;
  double initial_gc_train = 0.0, initial_gc_test = 0.0;  // the initial guess's GC errors
  NearTruth near_truth;    // the paper's Fig. 4, for the NLO estimate (empty when interrupted)
  NullSpaces null_spaces;  // what explains it: the GC error's blind directions
  bool interrupted = false;
  double seconds = 0.0;
};

/// Runs the demo. Throws what its stages throw (InputError, NumericalError).
DemoResult runDemo(const DemoOptions& options);

}  // namespace dynid
