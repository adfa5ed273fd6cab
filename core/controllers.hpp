// Joint-space trajectory tracking controllers that generate motion data.
//
// The paper's "GC sinusoidal controller" is TrackingController with a SinusoidalReference: joint i
// tracks q0_i + A_i sin(2 pi f_i t + phi_i), each joint at its own frequency, with
//     tau = Kp (q_des - q) + Kd (dq_des - dq) + g_ctrl(q),
// where g_ctrl is the gravity torque computed from the controller's own model (which need not be
// the true robot), then saturated to +-torque_limit.
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "core/data.hpp"

namespace dynid {

/// q_des(t) = q0 + A sin(2 pi f t + phi), per joint. Vectors of n entries; f in Hz, A in rad.
struct SinusoidalReference {
  Eigen::VectorXd q0, amplitude, frequency, phase;
};

/// dynid's one Fourier type: a finite Fourier series per joint (Swevers et al.), the reference of
/// `dynid simulate --controller fourier` and the motion `dynid excite` designs. With
/// w = 2 pi / period,
///   q_j(t) = offset_j + sum_k a_jk / (w k) sin(w k t) - b_jk / (w k) cos(w k t),  k = 1..H.
/// Periodic; at rest (dq = ddq = 0) at t = 0 and every multiple of the period when
/// sum_k a_jk = 0 and sum_k k b_jk = 0, which every design dynid makes satisfies.
struct FourierSeries {
  double period = 10.0;    // [s]
  Eigen::VectorXd offset;  // n [rad or m]
  Eigen::MatrixXd a, b;    // n x H [rad/s or m/s]
  int numJoints() const { return static_cast<int>(offset.size()); }
  int harmonics() const { return static_cast<int>(a.cols()); }
};

using Reference = std::variant<SinusoidalReference, FourierSeries>;

/// The default sinusoid frequencies of `dynid simulate`: 0.15 + 0.07 i Hz for joint i = 0..n-1.
Eigen::VectorXd defaultFrequencies(int n);
/// The midpoint of each joint's finite limits, else 0: the default centre of a reference.
Eigen::VectorXd defaultCentre(const Model& model);

/// Desired position, velocity and acceleration at time t [s]; each output gets n entries.
/// Throws InputError when the reference's vectors disagree in size.
void evaluateReference(const Reference& reference, double t, Eigen::VectorXd& q,
                       Eigen::VectorXd& dq, Eigen::VectorXd& ddq);

/// Stops in a reference: the reference's own time runs at a speed s(t) in [0, 1] that cycles
/// through `move` seconds of motion, then `hold` seconds at rest. Within the motion, s rises from 0
/// to 1 over the first `ramp` seconds and falls back over the last `ramp` (s = sin^2, so the
/// desired velocity and acceleration are continuous), so the arm slows to a stop, holds its pose
/// and starts again: q_des(t) = ref(tau(t)), tau' = s. The reference's time advances by
/// move - ramp per cycle. Each field finite; move > 2 ramp, hold >= 0, ramp > 0.
struct Pauses {
  double move = 4.0, hold = 2.0, ramp = 0.5;  // [s]
  /// The reference's time at t, and its first two derivatives. Throws InputError for bad fields.
  void warp(double t, double& tau, double& speed, double& rate) const;
  /// What is out of range ("ramp must be > 0 [s]"), or empty.
  std::string problem() const;
  /// Throws InputError naming `pauses` and problem().
  void check() const;
};

struct TrackingGains {
  Eigen::VectorXd kp;  // [N m / rad]
  Eigen::VectorXd kd;  // [N m s / rad]
};

/// Critically damped gains from the controller model's mass-matrix diagonal at q:
/// kp_i = M_ii (2 pi bandwidth)^2, kd_i = 2 damping M_ii (2 pi bandwidth).
TrackingGains defaultGains(const Model& model, const Eigen::VectorXd& q, double bandwidth_hz = 5.0,
                           double damping = 1.0);

/// The highest natural frequency [Hz] of the closed loop of diagonal PD gains kp on the mass matrix
/// at q: sqrt(max eig(M^-1 Kp)) / (2 pi). With defaultGains it can be far above the bandwidth when
/// joints are strongly coupled (the Panda's aligned axes 1, 3, 5, 7 at rest): a 1 kHz controller
/// then chatters between its torque limits.
double closedLoopFrequency(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& kp);

/// Gains from the effective inertias 1 / (M^-1)_ii at q (the inertia a joint sees when the others
/// move freely) instead of M_ii: every closed-loop mode then lies at most sqrt(n) times the
/// bandwidth (max eig(M^-1 Kp) <= trace = n w^2), whatever the coupling.
TrackingGains effectiveInertiaGains(const Model& model, const Eigen::VectorXd& q,
                                    double bandwidth_hz = 5.0, double damping = 1.0);

class TrackingController {
 public:
  /// `model` is the controller's own model (copied), used for gravity feed-forward. torque_limit
  /// has n entries (+inf for none). Throws InputError on size mismatches or non-positive limits.
  TrackingController(const Model& model, Reference reference, TrackingGains gains,
                     Eigen::VectorXd torque_limit);

  /// Torque at time t for the measured state (q, dq), saturated; n entries written to tau.
  void compute(double t, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& dq, Eigen::Ref<Eigen::VectorXd> tau);

  /// Stops the reference at its pauses (none by default). Throws what Pauses::check throws.
  void setPauses(const Pauses& pauses);
  /// The desired state at t, pauses included (n entries each).
  void desired(double t, Eigen::VectorXd& q, Eigen::VectorXd& dq, Eigen::VectorXd& ddq) const;
  const Reference& reference() const { return reference_; }
  const TrackingGains& gains() const { return gains_; }
  int numJoints() const { return model_.numJoints(); }

 private:
  Model model_;
  Data data_;
  Reference reference_;
  TrackingGains gains_;
  Eigen::VectorXd torque_limit_;
  std::optional<Pauses> pauses_;
  Eigen::VectorXd q_des_, dq_des_, ddq_des_, zero_;
};

}  // namespace dynid
