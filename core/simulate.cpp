#include "core/simulate.hpp"

#include <cmath>
#include <random>
#include <sstream>

#include "core/aba.hpp"
#include "core/errors.hpp"
#include "core/memory.hpp"

namespace dynid {

namespace {
void requirePositiveFinite(double x, const char* name) {
  if (!(std::isfinite(x) && x > 0.0))
    throw InputError(std::string("simulation ") + name + " must be positive and finite (got " +
                     std::to_string(x) + ")");
}
void requireNonNegativeFinite(double x, const char* name) {
  if (!(std::isfinite(x) && x >= 0.0))
    throw InputError(std::string("simulation ") + name + " must be >= 0 and finite");
}
}  // namespace

Trajectory simulate(const Model& truth, TrackingController& controller,
                    const SimulationOptions& options) {
  requirePositiveFinite(options.duration, "duration");
  requirePositiveFinite(options.step, "step");
  requirePositiveFinite(options.record_rate, "record rate");
  requireNonNegativeFinite(options.noise_q, "q noise");
  requireNonNegativeFinite(options.noise_dq, "dq noise");
  requireNonNegativeFinite(options.noise_tau, "tau noise");
  const int n = truth.numJoints();
  if (controller.numJoints() != n)
    throw InputError("controller has " + std::to_string(controller.numJoints()) +
                     " joints, model '" + truth.name + "' has " + std::to_string(n));
  const double period = 1.0 / options.record_rate;
  const double ratio = period / options.step;
  const long substeps = std::lround(ratio);
  if (substeps < 1 || std::abs(ratio - static_cast<double>(substeps)) > 1e-9 * ratio)
    throw InputError("the recording period 1/rate = " + std::to_string(period) +
                     " s is not a whole multiple of the integration step " +
                     std::to_string(options.step) + " s");
  const long samples = std::lround(std::floor(options.duration * options.record_rate + 1e-9)) + 1;
  if (samples > 100'000'000) throw InputError("simulation would record more than 1e8 samples");
  if (static_cast<double>(samples - 1) * static_cast<double>(substeps) > 1e9)
    throw InputError("simulation would take more than 1e9 integration steps (duration / step)");

  Trajectory out;
  requireMemory(static_cast<double>(samples) * (1 + 4 * n) * sizeof(double),
                "a simulation of " + std::to_string(samples) + " samples");
  out.resize(n, static_cast<int>(samples));
  Data data(truth);
  Eigen::VectorXd q, dq, ddq_ref;
  evaluateReference(controller.reference(), 0.0, q, dq, ddq_ref);
  Eigen::VectorXd tau(n);
  for (long k = 0; k < samples; ++k) {
    // Sample k: t = k / rate; record the state, the controller torque and the true acceleration.
    const double t = static_cast<double>(k) * period;
    if (!q.allFinite() || !dq.allFinite()) {
      std::ostringstream msg;
      msg << "simulation of '" << truth.name << "' diverged at t = " << t << " s";
      throw NumericalError(msg.str());
    }
    controller.compute(t, q, dq, tau);
    out.time[k] = t;
    out.q.col(k) = q;
    out.dq.col(k) = dq;
    out.tau.col(k) = tau;
    out.ddq.col(k) = aba(truth, data, q, dq, tau);
    if (k + 1 == samples) break;
    // Hold tau over the recording period.
    for (long s = 0; s < substeps; ++s)
      integratorStep(options.integrator, truth, data, q, dq, tau, options.step);
  }
  // Measurement noise on the recorded signals only.
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto add_noise = [&](Eigen::MatrixXd& m, double sigma) {
    if (sigma == 0.0) return;
    for (Eigen::Index k = 0; k < m.cols(); ++k)
      for (Eigen::Index i = 0; i < m.rows(); ++i) m(i, k) += sigma * normal(rng);
  };
  add_noise(out.q, options.noise_q);
  add_noise(out.dq, options.noise_dq);
  add_noise(out.tau, options.noise_tau);
  return out;
}

}  // namespace dynid
