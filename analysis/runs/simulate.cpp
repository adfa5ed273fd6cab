#include "analysis/runs/simulate.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include "analysis/records/document.hpp"
#include "analysis/records/excitation_record.hpp"
#include "analysis/records/upgrade.hpp"
#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"

namespace dynid {

FourierSeries randomFourier(const Eigen::VectorXd& q0, const Eigen::VectorXd& amplitude,
                            double base_frequency, int harmonics, std::uint64_t seed) {
  FourierSeries r;
  r.offset = q0;
  r.period = 1.0 / base_frequency;
  const int n = static_cast<int>(q0.size());
  r.a.resize(n, harmonics);
  r.b.resize(n, harmonics);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double w = 2.0 * std::numbers::pi * base_frequency;
  for (int i = 0; i < n; ++i) {
    double bound = 0.0;
    for (int k = 0; k < harmonics; ++k) {
      r.a(i, k) = uniform(rng);
      r.b(i, k) = uniform(rng);
      bound += (std::abs(r.a(i, k)) + std::abs(r.b(i, k))) / (w * (k + 1));
    }
    const double scale = bound > 0.0 ? amplitude[i] / bound : 0.0;
    r.a.row(i) *= scale;
    r.b.row(i) *= scale;
  }
  return r;
}

namespace {

/// The excitation design at `file`; one of an earlier version is read as it is, with a warning.
FourierSeries trackedDesign(const std::string& file, int num_joints,
                            std::vector<std::string>& warnings) {
  const FourierSeries design = readExcitationDesign(file, num_joints);
  const int version =
      documentVersion(parseJson(readFile(file), file), kExcitationDocument.schema_version);
  if (version < kExcitationDocument.schema_version)
    warnings.push_back(olderVersionNote(file, kExcitationDocument.kind, version,
                                        kExcitationDocument.schema_version));
  return design;
}

}  // namespace

SimulateOutcome simulateRun(const SimulateRequest& request) {
  if (request.one_period && !request.trajectory.empty()) {
    // The duration is the design's period, checked (memory included) as a given one would be.
    SimulateRequest resolved = request;
    resolved.simulation.duration =
        readExcitationDesign(request.trajectory, request.robot.numJoints()).period;
    resolved.one_period = false;
    return simulateRun(resolved);
  }
  request.check();
  const Model& truth = request.robot;
  const int n = truth.numJoints();
  // The controller's own model: another robot, or the truth, optionally perturbed.
  Model controller_model = request.controller_model.value_or(truth);
  if (controller_model.numJoints() != n)
    throw InputError("the controller's robot has " + std::to_string(controller_model.numJoints()) +
                     " joints, the robot has " + std::to_string(n));
  if (request.controller_perturb != 0.0)
    controller_model =
        perturbedModel(controller_model, request.controller_perturb, request.simulation.seed);

  Eigen::VectorXd q0 = request.q0.value_or(defaultCentre(truth));
  Reference reference;
  std::vector<std::string> warnings;  // the outcome's
  if (!request.trajectory.empty()) {
    const FourierSeries design = trackedDesign(request.trajectory, n, warnings);
    reference = design;
    q0 = design.offset;  // the default gains' configuration
  } else if (!request.fourier) {
    SinusoidalReference r;
    r.q0 = q0;
    r.amplitude = request.amplitude;
    r.frequency = request.frequency.value_or(defaultFrequencies(n));
    r.phase = request.phase.value_or(Eigen::VectorXd::Zero(n));
    reference = r;
  } else {
    reference = randomFourier(q0, request.amplitude, request.base_frequency, request.harmonics,
                              request.simulation.seed);
  }
  SimulateOutcome out;
  out.warnings = std::move(warnings);
  TrackingGains gains = defaultGains(controller_model, q0, request.bandwidth);
  out.gains_rule = "mass-matrix diagonal";
  // The paper's diagonal gains, unless the joints' coupling puts a closed-loop mode above 3 times
  // the bandwidth (the Panda's aligned axes at rest: its 1 kHz loop then chatters between the
  // torque limits); the effective inertias' gains keep every mode within sqrt(n) times it.
  if (!request.kp && !request.kd &&
      closedLoopFrequency(controller_model, q0, gains.kp) > 3.0 * request.bandwidth) {
    gains = effectiveInertiaGains(controller_model, q0, request.bandwidth);
    out.gains_rule = "effective inertia";
  }
  if (request.kp) gains.kp = *request.kp;
  if (request.kd) gains.kd = *request.kd;
  if (request.kp || request.kd) out.gains_rule = "given";
  Eigen::VectorXd tau_max(n);
  for (int i = 0; i < n; ++i) tau_max[i] = truth.limits[i].effort;
  if (request.tau_max) tau_max = *request.tau_max;

  TrackingController controller(controller_model, reference, gains, tau_max);
  if (request.pauses) controller.setPauses(*request.pauses);
  out.trajectory = simulate(truth, controller, request.simulation, request.disturbances,
                            request.disturbances.empty() ? nullptr : &out.external);
  // Tracking error RMS and peak torque.
  const Trajectory& t = out.trajectory;
  Eigen::VectorXd q_des, dq_des, ddq_des;
  double squared_error = 0.0;
  for (int k = 0; k < t.numSamples(); ++k) {
    controller.desired(t.time[k], q_des, dq_des, ddq_des);
    squared_error += (t.q.col(k) - q_des).squaredNorm();
  }
  out.tracking_rms = std::sqrt(squared_error / (static_cast<double>(t.numSamples()) * n));
  out.peak_torque = t.tau.cwiseAbs().maxCoeff();
  int saturated = 0;
  for (int k = 0; k < t.numSamples(); ++k) {
    if (k > 0)
      out.max_torque_step =
          std::max(out.max_torque_step, (t.tau.col(k) - t.tau.col(k - 1)).cwiseAbs().maxCoeff());
    // At the limit to within 1e-9 relative: the controller's saturation writes the limit itself.
    bool at_limit = false;
    for (int i = 0; i < n; ++i)
      at_limit = at_limit ||
                 (std::isfinite(tau_max[i]) && std::abs(t.tau(i, k)) >= tau_max[i] * (1.0 - 1e-9));
    saturated += at_limit;
  }
  out.saturated_share = t.numSamples() > 0 ? static_cast<double>(saturated) / t.numSamples() : 0.0;
  return out;
}

}  // namespace dynid
