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

#include "analysis/pipeline.hpp"
#include "core/controllers.hpp"
#include "core/model.hpp"
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

/// The limits a design keeps (n entries each) and the safety margins it keeps from them.
struct ExcitationLimits {
  Eigen::VectorXd q_min, q_max;  // [rad or m]
  Eigen::VectorXd dq_max;        // [rad/s or m/s]
  Eigen::VectorXd ddq_max;       // [rad/s^2 or m/s^2]
  Eigen::VectorXd tau_max;       // [N m or N]; +inf: no torque limit
  double torque_margin = 0.9;    // |tau| <= torque_margin tau_max (the model's torques are a guess)
  std::optional<double> floor;   // every link origin stays above this z in the base frame [m]
  double base_radius = 0.0;      // the last link's origin stays this far from the base z axis [m]
  std::vector<std::string> notes;  // the limits the model lacked and the defaults used instead
};

/// Limits given on the command line instead of the model's (n entries each, or absent).
struct LimitOverrides {
  std::optional<Eigen::VectorXd> q_min, q_max, dq_max, ddq_max, tau_max;
  double torque_margin = 0.9;
  std::optional<double> floor;
  double base_radius = 0.0;
};

/// Default limits for a model that has none: the peak speed and acceleration of `dynid simulate`'s
/// default sinusoid (0.5 rad at up to 0.5 Hz: 1.57 rad/s, 4.9 rad/s^2), rounded up, so a design is
/// never faster than the motion it is compared with.
inline constexpr double kDefaultVelocityLimit = 2.0;                     // [rad/s or m/s]
inline constexpr double kDefaultAccelerationLimit = 5.0;                 // [rad/s^2 or m/s^2]
inline constexpr double kDefaultRevoluteRange = 3.14159265358979323846;  // +- [rad]
inline constexpr double kDefaultPrismaticRange = 1.0;                    // +- [m]

/// The model's limits, replaced by the overrides where given and completed with the defaults above
/// where neither has one (each default is noted; no torque limit when none is known). Throws
/// InputError naming the joint and the limit for an empty position range, a non-positive
/// velocity, acceleration or torque limit, a torque margin outside (0, 1], a negative base radius
/// or a non-finite value.
ExcitationLimits excitationLimits(const Model& model, const LimitOverrides& overrides);

/// q_j(t) = offset_j + sum_k a_jk / (w k) sin(w k t) - b_jk / (w k) cos(w k t), k = 1..H,
/// w = 2 pi / period. Periodic; at rest (dq = ddq = 0) at t = 0 and every multiple of the period
/// when sum_k a_jk = 0 and sum_k k b_jk = 0, which every design dynid makes satisfies.
struct FourierDesign {
  double period = 10.0;    // [s]
  Eigen::VectorXd offset;  // n [rad or m]
  Eigen::MatrixXd a, b;    // n x H [rad/s or m/s]
  int numJoints() const { return static_cast<int>(offset.size()); }
  int harmonics() const { return static_cast<int>(a.cols()); }
  /// The same motion as a tracking controller's reference (core/controllers.hpp).
  FourierReference reference() const;
  /// q, dq, ddq at t = 0, 1/rate, ... up to the period inclusive, with tau their inverse dynamics
  /// under `model` (drives included). Throws InputError for a joint-count mismatch or rate <= 0.
  Trajectory sample(const Model& model, double rate) const;
};

/// The motion's extremes against the limits.
struct LimitCheck {
  double rate = 0.0;  // samples per second of the checked motion [Hz]
  Eigen::VectorXd q_low, q_high, dq_peak, ddq_peak, tau_peak;       // per joint
  double lowest_origin = std::numeric_limits<double>::quiet_NaN();  // min link-origin z [m]
  double nearest_base = std::numeric_limits<double>::quiet_NaN();   // last origin to base axis [m]
  std::vector<std::string> violations;  // one line per broken limit; empty: all hold
};
/// Checks every sample of `motion` (its tau included) against `limits`.
LimitCheck checkLimits(const Model& model, const Trajectory& motion,
                       const ExcitationLimits& limits);

struct ExciteRequest {
  Model robot;  // with the drive terms whose parameters the design must excite
  ExcitationCriterion criterion = ExcitationCriterion::kConditionUnit;
  double period = 10.0;                   // [s], > 0
  int harmonics = 5;                      // >= 2 (rest at both ends takes two per joint)
  std::optional<Eigen::VectorXd> offset;  // fixed offsets; default: optimised from mid-range
  ExcitationLimits limits;
  int starts = 8;          // multistart: seeded random coefficients
  int evaluations = 2000;  // COBYLA evaluations per start
  double max_seconds = std::numeric_limits<double>::infinity();  // the whole design
  double grid_rate = 25.0;       // samples per second of the optimiser's criterion and limits
  double check_rate = 1000.0;    // samples per second of the final check and the scores
  double torque_noise = 0.05;    // [N m] for the expected standard deviations
  int gc_segments = 100;         // the exact GC Jacobian's segments (as `dynid search`)
  double gc_horizon = 0.05;      // ... and horizon [s]
  StructuralOptions structural;  // the base parameters
  std::uint64_t seed = 1;
  int threads = 1;  // 0: all cores
  RunControl control;
};

struct ExciteStart {
  double objective = std::numeric_limits<double>::quiet_NaN();  // best feasible; NaN: none
  int evaluations = 0;
};

struct ExciteOutcome {
  FourierDesign design;
  BaseParameters base;
  ExcitationCriterion criterion = ExcitationCriterion::kConditionUnit;
  MotionScore score;     // the design, sampled at check_rate
  MotionScore baseline;  // `dynid simulate`'s default sinusoid over the same duration
  LimitCheck check;      // the design at check_rate: no violation
  LimitCheck baseline_check;
  /// Unit-column condition numbers, at the model's own parameters, of the GC residuals' exact
  /// Jacobian with respect to the base parameters (segments and horizon of the request, measured
  /// starts, RK4 at the check rate; the motion's inverse-dynamics torques held between samples),
  /// and of the first-order GC sensitivity M^-1 W1 (the "gc" criterion), design and sinusoid.
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

/// The design of an excitation.json written by `dynid excite`, read strictly (schema_version,
/// kind, unknown top-level keys, the design's fields and ranges) for a robot of `num_joints`
/// joints. Throws ParseError naming `file` and the field.
FourierDesign excitationDesignFrom(const nlohmann::json& document, const std::string& file,
                                   int num_joints);
/// The same from the file at `path` (readFile's limits apply).
FourierDesign readExcitationDesign(const std::string& path, int num_joints);

/// Throws InputError naming the joint when an offset (n entries) is not strictly inside its
/// position range: exciteRun's check, for callers that validate settings before the work.
void checkOffsets(const Model& model, const ExcitationLimits& limits,
                  const Eigen::VectorXd& offset);

/// `dynid simulate`'s default sinusoid for the model: amplitude 0.5 rad about the middle of the
/// limits, frequencies 0.15 + 0.07 i Hz, phases 0.
SinusoidalReference defaultSinusoid(const Model& model);

}  // namespace dynid
