// The combined estimator: one estimate that fits the torques and predicts the motion. It minimises
// the physically consistent problem's objective (the torque residuals in chi-square units plus
// the divergence from the prior, +inf outside the physical set) plus the GC residuals, over the
// full standard parameter vector, from the physically consistent estimate:
//     Phi(theta) = F(theta) / T0 + w G(P theta) / G0,
// T0 the torque data term at the start (the whole data's chi-square / 2, unexplained part
// included), G(beta) = GC / 2 and G0 its value at the start, w the relative weight (1: a 1 %
// lower GC error is worth a 1 % higher torque chi-square). Both criteria see only the base
// parameters beta = P theta; the prior decides the rest, as in pc, and every iterate is
// physically consistent (F is +inf outside the set). Levenberg-Marquardt on F's exact Hessian
// plus the Gauss-Newton model of G, whose Jacobian in beta is exact (Ceres's automatic
// differentiation through the rollout). docs/REFINEMENT.md, "The combined estimator".
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/parameters.hpp"
#include "core/run_control.hpp"
#include "search/gc_problem.hpp"

namespace dynid {

/// The torque term F(theta): convex, +inf outside its domain (the physical set), with its exact
/// gradient and Hessian there (identifiability's PhysicalProblem).
struct TorqueTerm {
  std::function<double(const Eigen::VectorXd&)> cost;
  std::function<void(const Eigen::VectorXd&, Eigen::VectorXd*, Eigen::MatrixXd*)> derivatives;
  /// T0 > 0: the torque data term at the start, the normaliser of F.
  double scale = 1.0;
};

struct CombinedOptions {
  /// w >= 0: the GC term's weight relative to the torque term's, each normalised by its value at
  /// the start (0: the start's problem alone).
  double gc_weight = 1.0;
  int max_iterations = 50;
  double max_seconds = 60.0;  // wall-time budget (0: none); held to within one segment's rollout
  /// Stop when an accepted step lowers Phi by less than this fraction.
  double function_tolerance = 1e-6;
  /// Hold the GC term at its noise floor (gcNoiseFloor at the start): the GC error below what
  /// the start's own torque residuals cause is noise, and fitting it biases the parameters (the
  /// rollouts' input torques are noisy, and a more damped model predicts noisy data better).
  bool noise_floor = true;
  int floor_draws = 8;  // residual sequences per segment for the floor
  /// The normalisers from elsewhere instead of the start's: G0 as a GC error (> 0; 0: the
  /// start's) and the noise floor (>= 0; negative: the start's, when noise_floor). A front of
  /// combined estimates gives every point the first start's, so that a weight means the same at
  /// every point whichever point it starts from.
  double given_gc = 0.0;
  double given_floor = -1.0;
  int num_threads = 1;
  RunControl control = {};  // its flag and deadline stop the estimator between rollouts
};

struct CombinedIteration {
  int iteration = 0;
  double cost = 0.0;     // Phi
  double torque = 0.0;   // F / T0
  double gc = 0.0;       // GC error (the problem's, weighted)
  double damping = 0.0;  // Levenberg-Marquardt's mu
  double seconds = 0.0;
};

struct CombinedResult {
  Eigen::VectorXd theta;  // standard parameters: physically consistent when the start was
  double initial_gc = 0.0, final_gc = 0.0;          // GC errors (sums of squares)
  double initial_torque = 0.0, final_torque = 0.0;  // F / T0
  double initial_cost = 0.0, final_cost = 0.0;      // Phi
  double gc_scale = 0.0;                            // G0 = initial_gc / 2
  double gc_weight = 0.0;                           // w (CombinedOptions::gc_weight)
  double gc_floor = 0.0;  // the GC error's noise floor (0 without CombinedOptions::noise_floor)
  std::vector<CombinedIteration> history;  // the start, then every accepted step
  std::string termination;   // "CONVERGENCE: ...", "NO_CONVERGENCE: ..." or "USER_SUCCESS: ..."
  int iterations = 0;        // Jacobian evaluations
  bool interrupted = false;  // stopped by the budget or the run control
  bool moved = false;        // at least one step was accepted
  double seconds = 0.0;
};

/// Phi's value at theta, with its parts (+inf when theta is outside F's domain).
struct CombinedValue {
  double cost = 0.0, torque = 0.0, gc = 0.0;
};

/// The GC term G over the estimator's parameter vector theta, however its rollouts are made: the
/// fixed-base rollouts of a GcProblem (refineCombined below) or a floating robot's
/// (search/floating/floating_combined.hpp).
struct GcTerm {
  /// The GC error at theta (segments that diverge counted at kMaxSegmentError; NaN when
  /// `control` stopped it).
  std::function<double(const Eigen::VectorXd& theta, const RunControl& control)> error;
  /// The GC residuals r at theta (the GC error is |r|^2) and their Jacobian in theta; false when a
  /// rollout diverges or `control` stops.
  std::function<bool(const Eigen::VectorXd& theta, const RunControl& control, Eigen::VectorXd* r,
                     Eigen::MatrixXd* J)>
      linearise;
  /// The GC error's noise floor at the start theta0 (a GC error), used with
  /// CombinedOptions::noise_floor when no floor is given; unset: 0.
  std::function<double(const Eigen::VectorXd& theta0)> floor;
};

/// The combined estimate over any GC term (the Levenberg-Marquardt of refineCombined below, over
/// the vector `theta0` has). Throws InputError for a bad weight or normaliser, an unset term or a
/// start outside F's domain; NumericalError when the start's rollouts diverge.
CombinedResult refineCombinedTerms(const TorqueTerm& torque, const GcTerm& gc,
                                   const Eigen::VectorXd& theta0, const CombinedOptions& options);

/// The combined estimate from `theta0` (p entries, inside F's domain, whose GC rollouts do not
/// diverge). Throws InputError on size mismatches, a joint-count mismatch, gc_weight < 0,
/// torque.scale <= 0 or a start outside F's domain; NumericalError when the start's rollouts
/// diverge (GC error not finite or zero).
CombinedResult refineCombined(const Model& structure, const GcProblem& problem,
                              const BaseCoordinates& base, const TorqueTerm& torque,
                              const Eigen::VectorXd& theta0, const CombinedOptions& options);

/// The GC error that the torque noise causes: the noise level of each joint's torque residual
/// (tau - the model's inverse dynamics) from its first differences (sqrt(mean (e_k+1 - e_k)^2 /
/// 2): white noise of variance s^2 has differences of variance 2 s^2, a smooth model error almost
/// none), then each segment rolled out under the recorded torques and under the recorded torques
/// plus white noise of that level (`draws` draws, fixed seed), the weighted squared end-state
/// differences averaged over the draws and summed over the segments. The same for any thread
/// count. Throws InputError on a joint-count mismatch.
///
/// `noise`, when given, is what the log's preparation knows of its torque noise (a prepared log's
/// first differences see little of it: its filter removed the differences' noise, not the noise
/// the rollouts integrate): white noise of noise->sigma per joint, low-passed by the zero-phase
/// Butterworth the log's torque went through, drawn over the whole log and sliced per segment.
struct TorqueNoise {
  Eigen::VectorXd sigma;  // per joint [N m], at the log's own rate
  int order = 0;          // the filter (0: none)
  double cutoff = 0.0;    // [Hz]
  double rate = 0.0;      // the log's sampling rate [Hz]
};
double gcNoiseFloor(const Model& model, const GcProblem& problem, int draws = 8,
                    int num_threads = 1, const TorqueNoise* noise = nullptr);

/// Phi at theta with the start's normalisers (for tests and reports): gc_scale is G0 and
/// gc_floor the GC error's noise floor (a GC error, as CombinedResult::gc_floor; 0: none).
CombinedValue combinedValue(const Model& structure, const GcProblem& problem,
                            const TorqueTerm& torque, const Eigen::VectorXd& theta,
                            double gc_weight, double gc_scale, double gc_floor = 0.0,
                            int num_threads = 1);

/// Phi's gradient at theta by the estimator's own formula (the one its steps use: F's exact
/// gradient plus, above the floor, w / G0 (1 - G_f / G) (J P)^T r with J the GC residuals'
/// Jacobian in beta): what the gradient check tests. Throws NumericalError when a rollout
/// diverges.
Eigen::VectorXd combinedGradient(const Model& structure, const GcProblem& problem,
                                 const BaseCoordinates& base, const TorqueTerm& torque,
                                 const Eigen::VectorXd& theta, double gc_weight, double gc_scale,
                                 double gc_floor = 0.0, int num_threads = 1);

/// Phi's gradient at theta over any GC term (combinedGradient's formula). Throws NumericalError
/// when a rollout diverges.
Eigen::VectorXd combinedGradientTerms(const TorqueTerm& torque, const GcTerm& gc,
                                      const Eigen::VectorXd& theta, double gc_weight,
                                      double gc_scale, double gc_floor = 0.0);

}  // namespace dynid
