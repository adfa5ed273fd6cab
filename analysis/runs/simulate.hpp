// The runs wing's room for dynid simulate: a robot under a tracking controller, its request and
// outcome. Nothing here prints or writes a report.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/controllers.hpp"
#include "core/model.hpp"
#include "core/simulate.hpp"
#include "core/trajectory.hpp"

namespace dynid {

struct SimulateRequest {
  Model robot;                            // the simulated truth
  std::optional<Model> controller_model;  // the controller's model (default: the robot)
  double controller_perturb = 0.0;        // its parameters perturbed by up to this fraction
  bool fourier = false;                   // seeded Fourier series instead of sinusoids
  std::string trajectory;                 // or: the design in this excitation.json (`dynid excite`)
  /// With a trajectory: simulation.duration is replaced by the design's period (one period, the
  /// motion the design was made for; the CLI sets this when --duration is not given).
  bool one_period = false;
  std::optional<Eigen::VectorXd> q0;  // centre [rad] (default: the middle of the limits)
  Eigen::VectorXd amplitude;          // n entries [rad]
  std::optional<Eigen::VectorXd> frequency, phase;  // sinusoidal [Hz], [rad]
  double base_frequency = 0.1;                      // fourier [Hz]
  int harmonics = 5;                                // fourier, >= 1
  std::optional<Eigen::VectorXd> kp, kd, tau_max;   // default gains and effort limits otherwise
  std::optional<Pauses> pauses;                     // stops in the motion (none by default)
  double bandwidth = 5.0;                           // for the default gains [Hz]
  SimulationOptions simulation;
  std::vector<Disturbance> disturbances;  // external pushes, recorded in SimulateOutcome::external

  /// Throws InputError naming the first numeric field out of its range (core/option_ranges.hpp,
  /// as dynid simulate's options). simulateRun checks its request first.
  void check() const;
};
struct SimulateOutcome {
  Trajectory trajectory;
  double tracking_rms = 0.0;  // RMS of q - q_desired over samples and joints [rad]
  double peak_torque = 0.0;   // max |tau| [N m]
  /// The largest torque change between two recorded samples, over joints [N m], and the share of
  /// samples at which some joint's torque is at its limit.
  double max_torque_step = 0.0, saturated_share = 0.0;
  /// The default gains' rule: "mass-matrix diagonal" (the paper's, kp_i = M_ii w^2) or
  /// "effective inertia" (1 / (M^-1)_ii, when the diagonal's would put a closed-loop mode above
  /// 3 times the bandwidth); "given" with `kp` or `kd`.
  std::string gains_rule;
  /// With disturbances: the external joint torque at every sample (n x samples) [N m].
  Eigen::MatrixXd external;
  std::vector<std::string> warnings;  // a trajectory of an earlier version read as it is
};
/// Simulates the robot under a tracking controller. Throws InputError for a controller model of
/// another joint count or harmonics < 1, ParseError for a bad `trajectory` file, and what
/// simulate() throws.
SimulateOutcome simulateRun(const SimulateRequest& request);

/// Seeded Fourier coefficients, scaled so each joint's excursion bound sum (|a|+|b|)/(w k) equals
/// its amplitude.
FourierSeries randomFourier(const Eigen::VectorXd& q0, const Eigen::VectorXd& amplitude,
                            double base_frequency, int harmonics, std::uint64_t seed);

// ---- identifiability ----

}  // namespace dynid
