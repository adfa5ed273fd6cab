// dynid's one COBYLA adapter (NLopt's LN_COBYLA): the searches' NLO rounds and the excitation
// design both run it. The caller keeps its own best point; a run that the objective stops, that
// round-off limits or that NLopt gives up on ends quietly with the reason.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dynid {

struct CobylaProblem {
  int dimension = 0;
  /// f(x) (dimension entries), or std::nullopt to stop the run now (a budget, Ctrl-C).
  std::function<std::optional<double>(const double* x)> objective;
  /// Inequality constraints c(x) <= 0: `inequalities` values written to c.
  int inequalities = 0;
  std::function<void(const double* x, double* c)> inequality;
  /// One optional equality constraint h(x) = 0, held to equality_tolerance.
  std::function<double(const double* x)> equality;
  double equality_tolerance = 0.0;
  std::vector<double> lower, upper;  // bounds (empty: none)
  std::vector<double> initial_step;  // one entry for every coordinate, or `dimension` entries
  int max_evaluations = 1000;
  double xtol_rel = 1e-10;
};

enum class CobylaEnd {
  kConverged,    // a tolerance was met
  kEvaluations,  // max_evaluations reached
  kStopped,      // the objective returned std::nullopt
  kRoundoff,     // round-off limited further progress
  kFailed,       // NLopt failed (e.g. a non-finite step); `message` says how
};

struct CobylaOutcome {
  CobylaEnd end = CobylaEnd::kConverged;
  std::string message;
};

/// Runs COBYLA from x (updated to its last point). Throws InputError for sizes that do not match
/// the dimension.
CobylaOutcome runCobyla(const CobylaProblem& problem, std::vector<double>& x);

}  // namespace dynid
