// dynid simulate: the robot under a tracking controller, recorded to a dataset CSV.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <random>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/dataset_csv.hpp"
#include "data/robots.hpp"

namespace dynid::cli {

namespace {

/// Seeded Fourier coefficients, scaled so each joint's excursion bound sum (|a|+|b|)/(w k) equals
/// its amplitude.
FourierReference randomFourier(const Eigen::VectorXd& q0, const Eigen::VectorXd& amplitude,
                               double base_frequency, int harmonics, std::uint64_t seed) {
  FourierReference r;
  r.q0 = q0;
  r.base_frequency = base_frequency;
  const int n = static_cast<int>(q0.size());
  r.sine.resize(n, harmonics);
  r.cosine.resize(n, harmonics);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double w = 2.0 * std::numbers::pi * base_frequency;
  for (int i = 0; i < n; ++i) {
    double bound = 0.0;
    for (int k = 0; k < harmonics; ++k) {
      r.sine(i, k) = uniform(rng);
      r.cosine(i, k) = uniform(rng);
      bound += (std::abs(r.sine(i, k)) + std::abs(r.cosine(i, k))) / (w * (k + 1));
    }
    const double scale = bound > 0.0 ? amplitude[i] / bound : 0.0;
    r.sine.row(i) *= scale;
    r.cosine.row(i) *= scale;
  }
  return r;
}

}  // namespace

int runSimulate(const std::vector<std::string>& args) {
  po::options_description options("dynid simulate");
  addRobotOptions(options);
  options.add_options()(
      "controller", po::value<std::string>()->default_value("sinusoidal"),
      "sinusoidal (q0 + A sin(2 pi f t + phase), the paper's GC sinusoidal controller) or fourier "
      "(seeded finite Fourier series)")(
      "q0", po::value<std::string>(), "centre of the motion [rad] (default: middle of the limits)")(
      "amplitude", po::value<std::string>()->default_value("0.5"),
      "amplitude per joint [rad] (one value for all); fourier: excursion bound")(
      "frequency", po::value<std::string>(),
      "sinusoidal: frequency per joint [Hz] (default 0.15, 0.22, 0.29, ...)")(
      "phase", po::value<std::string>(), "sinusoidal: phase per joint [rad] (default 0)")(
      "base-frequency", po::value<double>()->default_value(0.1), "fourier: base frequency [Hz]")(
      "harmonics", po::value<int>()->default_value(5), "fourier: number of harmonics")(
      "kp", po::value<std::string>(),
      "position gains [N m/rad] (default: M_ii (2 pi bandwidth)^2)")(
      "kd", po::value<std::string>(),
      "velocity gains [N m s/rad] (default: 2 M_ii 2 pi bandwidth)")(
      "bandwidth", po::value<double>()->default_value(5.0), "bandwidth for default gains [Hz]")(
      "tau-max", po::value<std::string>(),
      "torque limits [N m] (default: the model's effort limits)")(
      "controller-robot", po::value<std::string>(),
      "model used by the controller's gravity feed-forward (default: the simulated robot)")(
      "controller-perturb", po::value<double>()->default_value(0.0),
      "perturb the controller model's parameters by up to this fraction (seeded)")(
      "duration", po::value<double>()->default_value(10.0), "simulated time [s]")(
      "dt", po::value<double>()->default_value(1e-3), "integration step [s]")(
      "rate", po::value<double>()->default_value(1000.0), "recording and control rate [Hz]")(
      "integrator", po::value<std::string>()->default_value("rk4"), "rk4 or euler")(
      "seed", po::value<std::uint64_t>()->default_value(1), "seed for noise and random choices")(
      "noise-q", po::value<double>()->default_value(0.0), "std. dev. of noise on recorded q [rad]")(
      "noise-dq", po::value<double>()->default_value(0.0), "... on recorded dq [rad/s]")(
      "noise-tau", po::value<double>()->default_value(0.0), "... on recorded tau [N m]")(
      "out", po::value<std::string>()->required(), "dataset CSV to write");
  po::variables_map vm;
  const std::string usage = "dynid simulate --robot R [options] --out FILE.csv";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const std::string controller_kind = vm["controller"].as<std::string>();
  if (controller_kind != "sinusoidal" && controller_kind != "fourier")
    throw UsageError("--controller must be sinusoidal or fourier, not '" + controller_kind + "'");
  SimulationOptions sim;
  try {
    sim.integrator = parseIntegrator(vm["integrator"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(std::string("--integrator: ") + e.what());
  }
  sim.duration = vm["duration"].as<double>();
  sim.step = vm["dt"].as<double>();
  sim.record_rate = vm["rate"].as<double>();
  sim.noise_q = vm["noise-q"].as<double>();
  sim.noise_dq = vm["noise-dq"].as<double>();
  sim.noise_tau = vm["noise-tau"].as<double>();
  sim.seed = vm["seed"].as<std::uint64_t>();
  const int harmonics = vm["harmonics"].as<int>();
  if (harmonics < 1) throw UsageError("--harmonics must be at least 1");

  const Model truth = loadRobotFromOptions(vm);
  const int n = truth.numJoints();
  auto joint_vector = [&](const char* name, bool broadcast) {
    return parseJointVector(vm[name].as<std::string>(), name, n, broadcast);
  };
  const Eigen::VectorXd q0 = vm.count("q0") ? joint_vector("q0", false) : defaultCentre(truth);
  const Eigen::VectorXd amplitude = joint_vector("amplitude", true);

  // The controller's own model: another robot file, or the truth, optionally perturbed.
  Model controller_model = truth;
  if (vm.count("controller-robot")) {
    controller_model = loadRobot(vm["controller-robot"].as<std::string>(),
                                 {vm["drives"].as<bool>(), vm["strict"].as<bool>()});
    if (controller_model.numJoints() != n)
      throw InputError("--controller-robot has " + std::to_string(controller_model.numJoints()) +
                       " joints, the robot has " + std::to_string(n));
  }
  const double perturb = vm["controller-perturb"].as<double>();
  if (perturb != 0.0) controller_model = perturbedModel(controller_model, perturb, sim.seed);

  Reference reference;
  if (controller_kind == "sinusoidal") {
    SinusoidalReference r;
    r.q0 = q0;
    r.amplitude = amplitude;
    r.frequency = vm.count("frequency") ? joint_vector("frequency", true) : defaultFrequencies(n);
    r.phase = vm.count("phase") ? joint_vector("phase", true) : Eigen::VectorXd::Zero(n);
    reference = r;
  } else {
    reference =
        randomFourier(q0, amplitude, vm["base-frequency"].as<double>(), harmonics, sim.seed);
  }
  TrackingGains gains = defaultGains(controller_model, q0, vm["bandwidth"].as<double>());
  if (vm.count("kp")) gains.kp = joint_vector("kp", true);
  if (vm.count("kd")) gains.kd = joint_vector("kd", true);
  Eigen::VectorXd tau_max(n);
  for (int i = 0; i < n; ++i) tau_max[i] = truth.limits[i].effort;
  if (vm.count("tau-max")) tau_max = joint_vector("tau-max", true);

  TrackingController controller(controller_model, reference, gains, tau_max);
  const Trajectory trajectory = simulate(truth, controller, sim);
  const std::string out = vm["out"].as<std::string>();
  writeDatasetCsv(out, trajectory);

  // One-line summary: size, span, tracking error and peak torque.
  Eigen::VectorXd q_des, dq_des, ddq_des;
  double squared_error = 0.0;
  for (int k = 0; k < trajectory.numSamples(); ++k) {
    evaluateReference(reference, trajectory.time[k], q_des, dq_des, ddq_des);
    squared_error += (trajectory.q.col(k) - q_des).squaredNorm();
  }
  std::printf(
      "wrote %s: %s, %d samples x %d joints, t = 0..%g s, tracking error RMS %.3g rad, "
      "peak |tau| %.4g N m\n",
      out.c_str(), truth.name.c_str(), trajectory.numSamples(), n,
      trajectory.time[trajectory.numSamples() - 1],
      std::sqrt(squared_error / (static_cast<double>(trajectory.numSamples()) * n)),
      trajectory.tau.cwiseAbs().maxCoeff());
  return kExitOk;
}

}  // namespace dynid::cli
