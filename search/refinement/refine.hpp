// Refinement of a GC-error estimate by nonlinear least squares (Ceres): the search's rough answer
// turned into the best answer the data allow, with exact derivatives. The module has three parts:
// the cost functions (costs.hpp), the uncertainty in base coordinates (uncertainty.hpp) and this
// driver (the stages, the map back, the solver settings).
//
// Residuals: per segment i of a GcProblem (gc_error.hpp) the 2n weighted state-prediction errors
//     r_i = (w_q (q_hat_i - q_i), w_dq (dq_hat_i - dq_i))   at the segment's end,
// so that sum |r_i|^2 is the GC error. The rollout runs in ceres::Jet through the templated
// dynamics and integrator (automatic differentiation, no finite differences).
// With `estimate_initial_states`, each segment's start state s0_i (2n) is a parameter too, and the
// segment adds the 2n residuals w (s0_i - s0_i measured): the measured start is then one more
// noisy observation instead of being taken as exact (errors in variables). The Jacobian is block
// sparse (each segment sees the model parameters and its own start); it is solved by Schur
// elimination of the starts (SPARSE_SCHUR with SuiteSparse), so the cost grows linearly with the
// number of segments.
// Where a segment ends on the sample where the next one starts (contiguous segments, e.g.
// SegmentOptions::num_segments = 0), its end residual becomes
//     c w (s_hat_i - s0_{i+1})   (c = RefineOptions::continuity_weight)
// instead of w (s_hat_i - s_{i+1} measured): the segments join into one trajectory (multiple
// shooting) and every sample is observed once, through the start residual of the segment it
// starts. The estimate then uses each noisy sample as a measurement of a state the dynamics must
// connect to its neighbours, not as an exact start (with independent segments, profiling out the
// start gives back the plain GC residual up to a weighting, and hence nearly the same estimate).
// The starts are then no longer an independent set: SPARSE_NORMAL_CHOLESKY replaces SPARSE_SCHUR.
// The free parameters, their bounds and the parameter form are the search's (ParameterSpace);
// bounds are Ceres parameter bounds. With the total-mass constraint on, one more residual
// (sum of masses - total) / (1e-6 total) holds it to about 1e-6 relative at a solution with
// non-zero GC residuals, and exactly at a zero-residual one.
//
// Stages (with base coordinates): the residuals depend on the parameters only through the base
// parameters beta = P theta, so the problem is first solved in beta (full rank, no curvature from
// the parameter form, no bounds to stall on). The free parameters are then fitted to that beta
// within their bounds (the map back: Levenberg-Marquardt continuation from the estimate, the
// centre of the bounds and a few fixed pseudo-random points, pulled towards the centre with a
// weight taken to 0; the fit nearest the estimate among the best is kept) and polished in the free
// parameters (with the gauge). A noise-free start thus reaches the truth's beta even when the
// search left parameters at a bound, where LM in the free parameters alone stalls.
// Uncertainty is computed in base-parameter coordinates, never on the rank-deficient parameter set:
// the dynamics, hence the residuals, depend on the standard parameters theta only through
// beta = P theta. The residuals are differentiated with respect to beta at the estimate (theta
// moved along a right inverse of P), the starts are eliminated by their Schur complement, and
// cov(beta) = sigma^2 H^-1 with sigma^2 = sum r^2 / (residuals - unknowns).
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
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"

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
  int num_threads = 1;                 // Ceres's threads and the GC-error evaluations'
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
  const std::atomic<bool>* stop = nullptr;  // stops after the current iteration when set
  /// Called after each solver iteration, before `stop` is read, on the thread that called refine
  /// (e.g. to turn a pending Ctrl-C into `stop`); must not throw.
  std::function<void()> on_iteration = nullptr;
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
  double sigma2 = 0.0;            // residual variance
  int degrees_of_freedom = 0;     // residuals - unknowns
  int information_rank = 0;       // numerical rank of H (num_base when all are determined)
  Eigen::VectorXd beta_singular;  // singular values of d beta / d x (scaled)
  int free_parameter_rank = 0;    // how many beta directions the free parameters can move
  std::vector<FreeDirection> free_directions;
};

/// Refines x0 (numFree() entries, projected onto the bounds first). `base` may be null (no
/// uncertainty, no base stage). `termination`, `usable` and `iterations` are the final stage's;
/// the time budget and the stop flag cover both. Throws InputError when the problem's joint count
/// differs from the space's model, x0 has the wrong size or the continuity weight is negative or
/// not finite.
RefineResult refineGc(const ParameterSpace& space, const GcProblem& problem,
                      const Eigen::VectorXd& x0, const RefineOptions& options,
                      const BaseCoordinates* base = nullptr);

}  // namespace dynid
