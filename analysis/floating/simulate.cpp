#include "analysis/floating/simulate.hpp"

#include <random>

#include <Eigen/QR>

#include "core/floating/floating_rnea.hpp"

namespace dynid {

namespace {
/// Each force row's noise sd: a point contact's three forces, a frame contact's three moments
/// then three forces; the held base's (suspended) six rows come first, a frame's.
Eigen::VectorXd forceSd(const FloatingState& state, const FloatingSimulationOptions& o) {
  std::vector<double> sd;
  const auto frame = [&] {
    for (int k = 0; k < 3; ++k) sd.push_back(o.moment_noise);
    for (int k = 0; k < 3; ++k) sd.push_back(o.force_noise);
  };
  if (state.base_held) frame();
  for (int c : state.active) {
    if (o.contacts[static_cast<std::size_t>(c)].kind == Contact::Kind::kFrame)
      frame();
    else
      for (int k = 0; k < 3; ++k) sd.push_back(o.force_noise);
  }
  return Eigen::Map<Eigen::VectorXd>(sd.data(), static_cast<Eigen::Index>(sd.size()));
}
}  // namespace

FloatingSimulation simulateFloating(const FloatingModel& model,
                                    const FloatingSimulationOptions& options) {
  FloatingStructuralOptions sampling;
  sampling.structural.seed = options.seed;
  sampling.contacts = options.contacts;
  sampling.motion = options.motion;
  FloatingStateSampler sampler(model, sampling);
  FloatingData data(model);
  std::mt19937_64 rng(options.seed ^ 0x5eed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = model.numJoints();
  FloatingSimulation out;
  out.torque_variance = Eigen::VectorXd::Constant(n, options.torque_noise * options.torque_noise);
  for (int k = 0; k < options.samples; ++k) {
    FloatingState state = sampler.next();
    FloatingMeasurement m;
    m.J = sampler.jacobian(state);
    const Eigen::VectorXd generalized =
        floatingRnea(model, data, state.base, state.q, state.dq, state.ddq);
    m.Y = sampler.regressor(state);
    m.forces = Eigen::VectorXd::Zero(m.J.rows());
    if (m.J.rows() > 0)
      m.forces = m.J.leftCols<6>().transpose().completeOrthogonalDecomposition().solve(
          Eigen::VectorXd(generalized.head<6>()));
    m.tau = generalized.tail(n);
    if (m.J.rows() > 0) m.tau -= m.J.rightCols(n).transpose() * m.forces;
    const Eigen::VectorXd sd = forceSd(state, options);
    m.force_variance = sd.cwiseProduct(sd);
    for (Eigen::Index r = 0; r < m.forces.size(); ++r) m.forces[r] += sd[r] * normal(rng);
    for (int i = 0; i < n; ++i) m.tau[i] += options.torque_noise * normal(rng);
    out.samples.push_back(std::move(m));
  }
  return out;
}

}  // namespace dynid
