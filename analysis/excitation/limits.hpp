// The limits an excitation design keeps (positions, speeds, accelerations, torques with a margin,
// a floor and a base radius) and the check of a motion against them: excite.hpp designs within
// them, `dynid excite` and `dynid simulate --trajectory` check against them.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/trajectory.hpp"

namespace dynid {

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
  double torque_margin = ExcitationLimits{}.torque_margin;
  std::optional<double> floor;
  double base_radius = ExcitationLimits{}.base_radius;
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

/// Throws InputError naming the joint when an offset (n entries) is not strictly inside its
/// position range: exciteRun's check, for callers that validate settings before the work.
void checkOffsets(const Model& model, const ExcitationLimits& limits,
                  const Eigen::VectorXd& offset);

}  // namespace dynid
