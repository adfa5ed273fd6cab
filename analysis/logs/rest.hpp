// When a joint is at rest: the velocity within which a log's measured velocity cannot be told from
// zero, measured per joint from the log itself. Below it sign(dq) is noise, so the drive terms that
// need it are static friction there (core/drive_terms.hpp, core/model.hpp's rest_velocities).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// One joint's rest velocity and how it was found.
struct RestVelocity {
  /// |dq| <= velocity is at rest [rad/s or m/s]: the largest of `noise_level`, `chatter_level`
  /// and kRestVelocityFloor.
  double velocity = 0.0;
  /// 3 sigma of the velocity's white noise, sigma from the robust spread (1.4826 MAD) of dq less
  /// its local quadratic fit over kRestNoiseWindow samples (corrected for the fit's own share).
  double noise_level = 0.0;
  /// The 99th percentile of |dq| over the chatter: sign runs shorter than kRestChatterSeconds
  /// (but the first and the last, which the log's ends cut), when there are at least
  /// kRestMinChatterRuns of them and the noise in them is smooth (kRestChatterSmoothness: a
  /// filtered log's); 0 otherwise.
  double chatter_level = 0.0;
  long chatter_runs = 0;     // sign runs counted as chatter
  long samples_at_rest = 0;  // samples of the measured log with |dq| <= velocity
  long samples = 0;
  bool given = false;  // set by the user, not measured
  /// "chatter", "noise" or "floor": which level set `velocity` (or "given").
  std::string source() const;
};

inline constexpr int kRestNoiseWindow = 11;         // samples of the local quadratic fit
inline constexpr double kRestChatterSeconds = 0.2;  // longer sign runs are motion
inline constexpr long kRestMinChatterRuns = 5;      // fewer short runs: clean reversals
/// The chatter is the noise's only where the noise is smooth: the short runs' median |dq| above
/// this many sigma of the white noise (for white noise it is 0.67 sigma). White noise's runs are
/// covered by the noise level, and what stands above it in them is motion: a joint hunting in its
/// static friction after a stop slips at 10 to 20 times the noise in runs of tens of ms, which
/// the chatter's 99th percentile would take for noise (a simulated Panda with stick-slip
/// friction: 0.017 and 0.022 rad/s on joints 1 and 3 against 0.003 of noise, and the monitor took
/// the slips for rest). Measured: 0.67-0.76 on white noise with and without hunting, 1.3e4
/// through prepare's 10 Hz low-pass.
inline constexpr double kRestChatterSmoothness = 2.0;
/// No robot measures a joint velocity below this [rad/s or m/s]: one count of a 2^20-count
/// encoder (6e-6 rad) differenced over 0.6 s. A velocity free of noise (a simulator's, or a
/// prepared log's from noiseless positions) is at rest below it.
inline constexpr double kRestVelocityFloor = 1e-5;

/// Every joint's rest velocity from a log's velocities (dq: joints x samples) and its stamps
/// (time: samples, increasing). Throws InputError when the sizes disagree.
std::vector<RestVelocity> measureRestVelocities(const Eigen::MatrixXd& dq,
                                                const Eigen::VectorXd& time);

/// The rest velocities given by the user (one for every joint, or one per joint; each finite and
/// >= 0), counted against the log's velocities. Throws InputError naming `rest_velocity`.
std::vector<RestVelocity> givenRestVelocities(const std::vector<double>& given,
                                              const Eigen::MatrixXd& dq);

/// The velocities alone, one per joint (Model::rest_velocities).
std::vector<double> restThresholds(const std::vector<RestVelocity>& rest);

/// Samples with |dq_j| <= rest_j counted for each joint.
std::vector<long> samplesAtRest(const std::vector<double>& rest, const Eigen::MatrixXd& dq);

}  // namespace dynid
