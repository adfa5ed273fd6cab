// dynid simulate: the robot under a tracking controller, recorded to a dataset CSV.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/dataset_csv.hpp"
#include "reports/model_report.hpp"

namespace dynid::cli {

namespace {
void addSimulateOptions(po::options_description& options) {
  const SimulateRequest d;  // every default is the request's own
  options.add_options()(
      "controller", po::value<std::string>()->default_value("sinusoidal"),
      "sinusoidal (q0 + A sin(2 pi f t + phase), the paper's GC sinusoidal controller) or fourier "
      "(seeded finite Fourier series)")(
      "trajectory", po::value<std::string>(),
      "track the design in this excitation.json (dynid excite) instead; it repeats when "
      "--duration exceeds its period")(
      "q0", po::value<std::string>(), "centre of the motion [rad] (default: middle of the limits)")(
      "amplitude", po::value<std::string>()->default_value("0.5"),
      "amplitude per joint [rad] (one value for all); fourier: excursion bound")(
      "frequency", po::value<std::string>(),
      "sinusoidal: frequency per joint [Hz] (default 0.15, 0.22, 0.29, ...)")(
      "phase", po::value<std::string>(), "sinusoidal: phase per joint [rad] (default 0)")(
      "base-frequency", po::value<double>()->default_value(d.base_frequency))(
      "harmonics", po::value<int>()->default_value(d.harmonics))(
      "kp", po::value<std::string>(),
      "position gains [N m/rad] (default: M_ii (2 pi bandwidth)^2)")(
      "kd", po::value<std::string>(),
      "velocity gains [N m s/rad] (default: 2 M_ii 2 pi bandwidth)")(
      "bandwidth", po::value<double>()->default_value(d.bandwidth))(
      "tau-max", po::value<std::string>(),
      "torque limits [N m] (default: the model's effort limits)")(
      "controller-robot", po::value<std::string>(),
      "model used by the controller's gravity feed-forward (default: the simulated robot)")(
      "controller-perturb", po::value<double>()->default_value(d.controller_perturb))(
      "duration", po::value<double>()->default_value(d.simulation.duration))(
      "dt", po::value<double>()->default_value(d.simulation.step))(
      "rate", po::value<double>()->default_value(d.simulation.record_rate))(
      "integrator", po::value<std::string>()->default_value("rk4"), "rk4 or euler")(
      "seed", po::value<std::uint64_t>()->default_value(d.simulation.seed),
      "seed for noise and random choices")(
      "noise-q", po::value<double>()->default_value(d.simulation.noise_q))(
      "noise-dq", po::value<double>()->default_value(d.simulation.noise_dq))(
      "noise-tau", po::value<double>()->default_value(d.simulation.noise_tau))(
      "out", po::value<std::string>()->required(), "dataset CSV to write");
}
}  // namespace

int runSimulate(const std::vector<std::string>& args) {
  po::options_description options("dynid simulate");
  addRobotOptions(options);
  addSimulateOptions(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid simulate --robot R [options] --out FILE.csv", vm))
    return kExitOk;
  const std::string controller = vm["controller"].as<std::string>();
  if (controller != "sinusoidal" && controller != "fourier")
    throw UsageError("--controller must be sinusoidal or fourier, not '" + controller + "'");
  const IntegratorType integrator = parseOption(vm, "integrator", parseIntegrator);
  const int harmonics = vm["harmonics"].as<int>();
  SimulateRequest request;
  request.robot = loadRobotFromOptions(vm);
  SimulationOptions& sim = request.simulation;
  sim.integrator = integrator;
  sim.duration = vm["duration"].as<double>();
  sim.step = vm["dt"].as<double>();
  sim.record_rate = vm["rate"].as<double>();
  sim.noise_q = vm["noise-q"].as<double>();
  sim.noise_dq = vm["noise-dq"].as<double>();
  sim.noise_tau = vm["noise-tau"].as<double>();
  sim.seed = vm["seed"].as<std::uint64_t>();
  request.harmonics = harmonics;
  request.fourier = controller == "fourier";
  refuseUnused(vm, !request.fourier, {"frequency", "phase"},
               "applies to --controller sinusoidal, not fourier");
  refuseUnused(vm, request.fourier, {"base-frequency", "harmonics"},
               "applies to --controller fourier, not sinusoidal");
  if (vm.count("trajectory")) {
    for (const char* other : {"q0", "frequency", "phase"})
      if (vm.count(other))
        throw UsageError(std::string("--") + other + " does not apply to --trajectory");
    if (!vm["controller"].defaulted() || !vm["amplitude"].defaulted())
      throw UsageError("--trajectory replaces --controller and --amplitude: give one or the other");
    request.trajectory = vm["trajectory"].as<std::string>();
  }
  const int n = request.robot.numJoints();
  request.q0 = optionalJointVector(vm, "q0", n, false);
  request.amplitude = *optionalJointVector(vm, "amplitude", n, true);
  request.frequency = optionalJointVector(vm, "frequency", n, true);
  request.phase = optionalJointVector(vm, "phase", n, true);
  request.base_frequency = vm["base-frequency"].as<double>();
  request.kp = optionalJointVector(vm, "kp", n, true);
  request.kd = optionalJointVector(vm, "kd", n, true);
  request.tau_max = optionalJointVector(vm, "tau-max", n, true);
  request.bandwidth = vm["bandwidth"].as<double>();
  if (vm.count("controller-robot"))
    request.controller_model = loadOtherRobot(vm, "controller-robot");
  request.controller_perturb = vm["controller-perturb"].as<double>();
  const SimulateOutcome outcome = simulateRun(request);
  const std::string out = vm["out"].as<std::string>();
  writeDatasetCsv(out, outcome.trajectory);
  std::cout << simulateSummary(request.robot, outcome, out);
  return kExitOk;
}

}  // namespace dynid::cli
