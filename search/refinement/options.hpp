// The refinement's options and results (refine.hpp runs it; costs.hpp and uncertainty.hpp read
// them). How refinement works: docs/REFINEMENT.md, "How the refinement works".
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/parameters.hpp"
#include "core/run_control.hpp"

namespace dynid {

struct RefineOptions {
  bool estimate_initial_states = false;
  /// With estimate_initial_states: the weight c of the gap between a segment's predicted end and
  /// the next segment's start, relative to the measurement weights, where the two meet; 0 keeps
  /// every segment's end residual on its measured end state (independent segments).
  double continuity_weight = 10.0;
  int max_iterations = 200;            // per stage
  double function_tolerance = 1e-16;   // Ceres: relative cost change
  double gradient_tolerance = 1e-20;   // Ceres: max-norm of the projected gradient
  double parameter_tolerance = 1e-14;  // Ceres: relative step size
  double max_seconds = 0.0;            // wall-time budget (0: none)
  int num_threads = 1;                 // threads of the segment and GC-error evaluations
  /// With base coordinates: hold the free parameters' components along the directions that leave
  /// beta unchanged at the start (a gauge), so the solver does not wander along them into the
  /// bounds. The GC residuals depend on beta only, so this changes no beta the solver can reach.
  bool fix_gauge = true;
  /// With base coordinates: solve first in beta (full rank, and free of the parameter form's
  /// curvature), map the solution back to the free parameters within their bounds, then polish
  /// in the free parameters. Without it the free parameters are refined directly.
  bool base_stage = true;
  /// Pseudo-random starts (fixed seed) of the map back from beta to the free parameters, besides
  /// the current estimate and the centre of the bounds.
  int map_back_starts = 14;
  /// With base coordinates: the uncertainty of the result in beta (a Jacobian of every segment
  /// after the solve, inside the time budget: the last stage stops an iteration earlier to leave
  /// it room, and it is skipped, said in RefineResult::uncertainty_skipped, when there is none).
  /// Off: RefineResult's base fields stay empty.
  bool uncertainty = true;
  /// Stops after the current iteration when control.check() says so (its flag, its deadline;
  /// on_check runs on the calling thread after each solver iteration).
  RunControl control = {};
  /// Called after every solver iteration of either stage with it and the share of the run done:
  /// of the time budget when there is one, else of max_iterations (for progress on a terminal).
  std::function<void(const struct RefineIteration&, double done)> on_iteration{};
};

struct RefineIteration {
  std::string stage;  // "base" (in beta) or "parameters" (in the free parameters)
  int iteration = 0;
  double cost = 0.0;  // Ceres cost 1/2 sum r^2 (with the start and mass residuals)
  double gradient_max_norm = 0.0;
  double seconds = 0.0;
};

/// A direction of the free parameters that leaves beta unchanged (to first order) at the estimate:
/// the GC error cannot determine movement along it.
struct FreeDirection {
  std::vector<std::pair<std::string, double>> combination;  // largest |coefficient| = 1
};

struct RefineResult {
  Eigen::VectorXd x;               // refined free parameters (ParameterSpace)
  Eigen::MatrixXd initial_states;  // 2n x segments: (q; dq) at each start, estimated or measured
  double initial_gc = 0.0;         // GC error (measured starts) at the start and the end
  double final_gc = 0.0;
  double initial_cost = 0.0, final_cost = 0.0;  // Ceres costs, of the first and the last stage
  std::vector<RefineIteration> history;         // both stages, in order
  // The base stage (RefineOptions::base_stage): its GC error, iterations and termination, and how
  // closely the free parameters reproduce its beta after the map back (RMS of the differences
  // relative to |beta|, see baseParameterError); map_back_used is false when the mapped-back point
  // predicted worse than the start and the polish started from the start instead.
  bool base_stage = false;
  Eigen::VectorXd base_beta;  // the base stage's solution (unconstrained by the parameter form)
  double base_gc = 0.0;
  int base_iterations = 0;
  std::string base_termination;
  double map_back_error = 0.0;
  bool map_back_used = false;
  std::string termination;  // Ceres termination type and message ("USER_SUCCESS: ..." on stop)
  bool usable = false;      // Ceres's IsSolutionUsable()
  bool interrupted = false;
  int iterations = 0;
  double seconds = 0.0;
  std::string linear_solver;
  int chained_segments = 0;           // segments whose end residual is on the next start
  int gauge_dimension = 0;            // free directions held at the start (fix_gauge)
  std::vector<std::string> at_bound;  // free parameters at a bound (to 1e-9 of their range)

  // In base coordinates (when BaseCoordinates are given).
  Eigen::VectorXd beta;
  Eigen::MatrixXd beta_covariance;
  Eigen::VectorXd beta_std_dev;
  std::string uncertainty_skipped;  // why the uncertainty was not computed (budget), or empty
  double sigma2 = 0.0;              // residual variance
  int degrees_of_freedom = 0;       // residuals - unknowns
  int information_rank = 0;         // numerical rank of H (num_base when all are determined)
  Eigen::VectorXd beta_singular;    // singular values of d beta / d x (scaled)
  int free_parameter_rank = 0;      // how many beta directions the free parameters can move
  std::vector<FreeDirection> free_directions;
};

}  // namespace dynid
