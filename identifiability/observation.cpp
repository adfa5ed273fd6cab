#include "identifiability/observation.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/memory.hpp"
#include "core/regressor.hpp"

namespace dynid {

namespace {
void appendSample(const Model& model, Data& data, int k, const Eigen::VectorXd& q,
                  const Eigen::VectorXd& dq, const Eigen::VectorXd& ddq, Observation& out) {
  const int n = model.numJoints();
  out.W.middleRows(static_cast<Eigen::Index>(k) * n, n) =
      jointTorqueRegressor(model, data, q, dq, ddq);
}
}  // namespace

void checkFiniteSample(const Trajectory& trajectory, int k) {
  const char* names[] = {"q", "dq", "ddq", "tau"};
  const Eigen::MatrixXd* blocks[] = {&trajectory.q, &trajectory.dq, &trajectory.ddq,
                                     &trajectory.tau};
  for (int b = 0; b < 4; ++b)
    for (Eigen::Index j = 0; j < blocks[b]->rows(); ++j)
      if (!std::isfinite((*blocks[b])(j, k))) {
        std::ostringstream msg;
        msg << "sample " << k + 1 << " (t = " << trajectory.time[k] << " s): " << names[b] << j + 1
            << " is not finite";
        throw InputError(msg.str());
      }
}

void checkFiniteSamples(const Trajectory& trajectory) {
  if (trajectory.q.allFinite() && trajectory.dq.allFinite() && trajectory.ddq.allFinite() &&
      trajectory.tau.allFinite())
    return;
  for (int k = 0; k < trajectory.numSamples(); ++k) checkFiniteSample(trajectory, k);
}

Observation observationFromTrajectory(const Model& model, const Trajectory& trajectory) {
  const int n = model.numJoints(), samples = trajectory.numSamples();
  if (trajectory.numJoints() != n)
    throw InputError("the data has " + std::to_string(trajectory.numJoints()) + " joints, model '" +
                     model.name + "' has " + std::to_string(n));
  Observation out;
  out.num_samples = samples;
  out.num_joints = n;
  out.layout = model.parameterLayout();
  // W, and the base regressor and its QR factor that every estimator builds from it.
  const double rows = static_cast<double>(samples) * n;
  requireMemory(3.0 * rows * out.layout.size() * sizeof(double),
                "the observation matrix of " + std::to_string(samples) + " samples x " +
                    std::to_string(n) + " joints x " + std::to_string(out.layout.size()) +
                    " parameters (with its factorisation)");
  out.W.resize(static_cast<Eigen::Index>(samples) * n, out.layout.size());
  out.tau.resize(static_cast<Eigen::Index>(samples) * n);
  Data data(model);
  Eigen::VectorXd q(n), dq(n), ddq(n);
  for (int k = 0; k < samples; ++k) {
    checkFiniteSample(trajectory, k);  // before the value reaches the regressor
    q = trajectory.q.col(k);
    dq = trajectory.dq.col(k);
    ddq = trajectory.ddq.col(k);
    appendSample(model, data, k, q, dq, ddq, out);
    out.tau.segment(static_cast<Eigen::Index>(k) * n, n) = trajectory.tau.col(k);
  }
  return out;
}

std::pair<double, double> randomStateRange(const Model& model, int i) {
  const JointLimits& l = model.limits[static_cast<std::size_t>(i)];
  if (std::isfinite(l.lower) && std::isfinite(l.upper)) return {l.lower, l.upper};
  const double span = model.joint_types()[i] == JointType::kPrismatic ? 1.0 : std::numbers::pi;
  return {-span, span};
}

Observation observationFromRandomStates(const Model& model, int num_samples, std::uint64_t seed) {
  if (num_samples < 1) throw InputError("need at least one random state");
  const int n = model.numJoints();
  Observation out;
  out.num_samples = num_samples;
  out.num_joints = n;
  out.layout = model.parameterLayout();
  out.W.resize(static_cast<Eigen::Index>(num_samples) * n, out.layout.size());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Data data(model);
  Eigen::VectorXd q(n), dq(n), ddq(n);
  for (int k = 0; k < num_samples; ++k) {
    for (int i = 0; i < n; ++i) {
      const auto [lower, upper] = randomStateRange(model, i);
      q[i] = lower + (upper - lower) * unit(rng);
      dq[i] = -2.0 + 4.0 * unit(rng);
      ddq[i] = -5.0 + 10.0 * unit(rng);
    }
    appendSample(model, data, k, q, dq, ddq, out);
  }
  out.tau = out.W * model.standardParameters();
  return out;
}

}  // namespace dynid
