// Excitation design (`dynid excite`): a periodic finite Fourier series per joint (Swevers et al.
// 1997) that starts and ends at rest, optimised with NLopt for how well the data it produces
// would determine the base parameters, within the joint position, velocity, acceleration and
// torque limits (and, optionally, above a floor and away from the base). docs/EXCITATION.md
// describes the method and its guarantees.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/excitation/limits.hpp"
#include "core/controllers.hpp"
#include "core/model.hpp"
#include "core/run_control.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/excitation.hpp"

namespace dynid {

/// What a design minimises: the unit-column condition number of the base regressor ("cond"), its
/// condition number in SI units ("cond-unscaled"), -log det of its information matrix per row
/// ("d-optimal"), or the GC criterion ("gc"): the unit-column condition number of M(q)^-1 W1, the
/// first-order sensitivity of the state a short horizon ahead to the base parameters (docs/
/// EXCITATION.md derives it), or "relative-sd": the RMS over the base parameters of their expected
/// standard deviation relative to the model's own values (A-optimality in relative units: the
/// expected relative base-parameter error of least squares, MotionScore::relative_rms). Every
/// design reports all of them, and the condition number of the exact GC Jacobian over the
/// search's segments (ExciteOutcome::gc).
enum class ExcitationCriterion { kConditionUnit, kCondition, kDOptimal, kGc, kRelativeSd };
const std::vector<std::string>& excitationCriterionNames();
std::string excitationCriterionName(ExcitationCriterion criterion);
/// Throws InputError naming the accepted names.
ExcitationCriterion parseExcitationCriterion(const std::string& name);

/// A design's motion (core/controllers.hpp's FourierSeries) sampled at t = 0, 1/rate, ... up to
/// the period inclusive: q, dq, ddq, with tau their inverse dynamics under `model` (drives
/// included). Throws InputError for a joint-count mismatch or rate <= 0.
Trajectory sampleFourier(const FourierSeries& design, const Model& model, double rate);

/// exciteRun's starts when the request leaves them at 0.
inline constexpr int kDefaultStarts = 8, kPayloadStarts = 16;

struct ExciteRequest {
  Model robot;  // with the drive terms whose parameters the design must excite
  ExcitationCriterion criterion = ExcitationCriterion::kConditionUnit;
  double period = 10.0;                   // [s], > 0
  int harmonics = 5;                      // >= 2 (rest at both ends takes two per joint)
  std::optional<Eigen::VectorXd> offset;  // fixed offsets; default: optimised from mid-range
  ExcitationLimits limits;
  /// Multistart: seeded random coefficients; 0: kDefaultStarts, or kPayloadStarts for a payload
  /// motion (its d-optimal design has many local optima: docs/PAYLOAD.md).
  int starts = 0;
  int evaluations = 2000;                                        // COBYLA evaluations per start
  double max_seconds = std::numeric_limits<double>::infinity();  // the whole design
  double grid_rate = 25.0;       // samples per second of the optimiser's criterion and limits
  double check_rate = 1000.0;    // samples per second of the final check and the scores
  double torque_noise = 0.05;    // [N m] for the expected standard deviations
  int gc_segments = 100;         // the exact GC Jacobian's segments (as `dynid search`)
  double gc_horizon = 0.05;      // ... and horizon [s]
  StructuralOptions structural;  // the base parameters
  /// A payload motion: the design determines only this link's 10 parameters (a payload attached
  /// to it, the rest of the arm known; identifiability's blockBaseParameters), within 20 s.
  std::optional<int> payload_link;
  /// In a payload motion, the share of their range (about its middle, or the fixed offset) that
  /// the joints before the wrist (all but the last three) may use: below 1 the motion is mainly
  /// the wrist's (a cell with little room), at some cost in what it determines
  /// (docs/PAYLOAD.md); 1: their whole range.
  double payload_proximal_share = 1.0;
  std::uint64_t seed = 1;
  int threads = 1;  // 0: all cores
  RunControl control;

  /// Throws InputError naming the first field out of its range (core/option_ranges.hpp, as dynid
  /// excite's options, by field name), for a GC horizon that is not a whole number of check-rate
  /// samples within the period, limits or offsets that do not fit the robot, a grid over 1e6
  /// points or a check-rate sampling over the memory limit. exciteRun checks its request first.
  void check() const;
};

struct ExciteStart {
  double objective = std::numeric_limits<double>::quiet_NaN();  // best feasible; NaN: none
  int evaluations = 0;
};

struct ExciteOutcome {
  FourierSeries design;
  BaseParameters base;
  ExcitationCriterion criterion = ExcitationCriterion::kConditionUnit;
  std::optional<int> payload_link;  // the design is a payload motion for this link
  MotionScore score;                // the design, sampled at check_rate
  MotionScore baseline;             // `dynid simulate`'s default sinusoid over the same duration
  LimitCheck check;                 // the design at check_rate: no violation
  LimitCheck baseline_check;
  /// Unit-column condition numbers, at the model's own parameters, of the GC residuals' exact
  /// Jacobian with respect to the base parameters (segments and horizon of the request, measured
  /// starts, RK4 at the check rate; the motion's inverse-dynamics torques held between samples),
  /// and of the first-order GC sensitivity M^-1 W1 (the "gc" criterion), design and sinusoid.
  /// gc and baseline_gc are NaN (not computed) when the run was interrupted.
  double gc = 0.0, baseline_gc = 0.0, gc_first_order = 0.0, baseline_gc_first_order = 0.0;
  int gc_segments = 0;
  double gc_horizon = 0.0;
  ExcitationLimits limits;
  double torque_noise = 0.0, check_rate = 0.0, grid_rate = 0.0;
  std::vector<ExciteStart> starts;
  int best_start = -1;
  double shrink = 1.0;      // factor on the coefficients that made the check at check_rate pass
  std::string termination;  // "evaluations", "seconds" or "interrupted"
  long evaluations = 0;
  double seconds = 0.0;
  std::uint64_t seed = 1;
};

/// Designs the motion. Starts run in parallel; each start's seed depends only on `seed` and its
/// index, so the design is the same for any thread count unless the time budget or an interrupt
/// ends it early (then the best design so far is kept). Throws InputError for settings out of
/// range (period, harmonics, starts, evaluations, rates, noise, offsets outside the limits), and
/// Error when no start meets the limits (with the limit that could not be met).
ExciteOutcome exciteRun(const ExciteRequest& request);

/// `dynid simulate`'s default sinusoid for the model: amplitude 0.5 rad about the middle of the
/// limits, frequencies 0.15 + 0.07 i Hz, phases 0.
SinusoidalReference defaultSinusoid(const Model& model);

}  // namespace dynid
