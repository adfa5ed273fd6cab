// dynid simulate: the robot under a tracking controller, recorded to a dataset CSV.
#include <charconv>
#include <cmath>
#include <iostream>

#include "analysis/floating/standing.hpp"
#include "cli/command_floating.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/parallel.hpp"
#include "data/dataset_csv.hpp"
#include "reports/model_report.hpp"

namespace dynid::cli {

namespace {
void addFloatingSimulateOptions(po::options_description& options);

void addSimulateOptions(po::options_description& options) {
  const SimulateRequest d;  // every default is the request's own
  options.add_options()(
      "controller", po::value<std::string>()->default_value("sinusoidal"),
      "sinusoidal (q0 + A sin(2 pi f t + phase), the paper's GC sinusoidal controller) or fourier "
      "(seeded finite Fourier series)")(
      "trajectory", po::value<std::string>(),
      "track the design in this excitation.json (dynid excite) instead: one period unless "
      "--duration is given (it repeats when --duration exceeds its period)")(
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
      "disturbance", po::value<std::vector<std::string>>()->composing(),
      "an external push (repeatable): joint=J,torque=T,at=S,for=D [N m, s] or "
      "link=L,force=fx:fy:fz[,moment=mx:my:mz],at=S,for=D [N, N m, base-frame axes, at the link "
      "frame's origin]; J and L by name or 1-based index; a short `for` makes an impulse")(
      "pauses", po::value<std::string>(),
      "stops in the motion: move=M,hold=H[,ramp=R] [s]: M seconds of motion (slowing to a stop "
      "over its last R, starting over its first R; default 0.5), then H seconds holding the pose, "
      "over and over")(
      "stiction", po::bool_switch(),
      "a joint stops at zero velocity and sticks while its static friction can hold it, as a real "
      "arm's does (default: its friction law's value, Coulomb's sign chattering about a resting "
      "joint, as identify's and search's rollouts integrate it)")(
      "truth-out", po::value<std::string>(),
      "with --disturbance: the applied external joint torques, t,tau_ext1.. (default: OUT with "
      ".truth.csv for .csv; - for standard output)")(
      "out", po::value<std::string>()->required(),
      "dataset CSV to write, or - for standard output");
  addFloatingSimulateOptions(options);
}

/// simulate --floating-base's own options (docs/FLOATING.md).
void addFloatingSimulateOptions(po::options_description& options) {
  addFloatingOptions(options,
                     "writes a floating dataset of random states (docs/FLOATING.md): the joint "
                     "torques and contact wrenches inverse dynamics needs, with noise");
  options.add_options()("samples", po::value<int>())("noise-force",
                                                     po::value<double>()->default_value(0.0))(
      "noise-moment", po::value<double>()->default_value(0.0))(
      "friction-cone", po::value<double>()->default_value(0.0))(
      "sole", po::value<std::string>(),
      "with --floating-base and --friction-cone: a flat sole under every frame contact, "
      "LENGTH,WIDTH [m] (a rectangle along its frame's x and y, centred at its origin) or its "
      "corners X1,Y1,X2,Y2,X3,Y3[,...] [m] in the frame's x-y plane: its wrench is that of "
      "corner forces within the cones about the sole's normal, so its centre of pressure stays "
      "in the corners' convex hull")(
      "stand-tilts", po::value<std::string>(),
      "with --floating-base and --trajectory: the stand's orientations R1,P1[,R2,P2,...] (roll "
      "and pitch [rad]), the design simulated for one period at each in turn, 1 s apart (a stand "
      "tilted between recordings: one orientation cannot show the whole body's first moment "
      "along gravity; default: those the design chose, dynid excite --stands)")(
      "motion-from", po::value<std::string>(),
      "with --floating-base: the motion of this floating dataset (its time, base and joints, "
      "sample by sample; its torques and wrenches not read) instead of random states, the "
      "contacts holding where its contact:F flags say (default contacts: its flagged frames)")(
      "stance", po::value<std::string>(),
      "with --floating-base and --contacts: a standing robot's joints at rest, q1,...,qn [rad]; "
      "the base then sways (--sway, --turn, --sway-period) above contacts that stay where the "
      "stance puts them, the legs following, --samples at --rate (default 200 Hz)")(
      "sway", po::value<double>()->default_value(StandingMotionRequest{}.sway),
      "with --stance: the base origin's amplitude along each world axis [m]")(
      "turn", po::value<double>()->default_value(StandingMotionRequest{}.turn),
      "with --stance: the amplitude of the base's turn about one axis [rad]")(
      "sway-period", po::value<double>()->default_value(StandingMotionRequest{}.period),
      "with --stance: the period the sway repeats over [s]");
}

/// The index (0-based) of `what` among `names`, or its 1-based number. UsageError otherwise.
int namedIndex(const std::string& what, const std::vector<std::string>& names, const char* kind,
               const std::string& spec) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == what) return static_cast<int>(i);
  int number = 0;
  const auto [end, error] = std::from_chars(what.data(), what.data() + what.size(), number);
  if (error == std::errc() && end == what.data() + what.size() && number >= 1 &&
      number <= static_cast<int>(names.size()))
    return number - 1;
  throw UsageError(std::string("--disturbance '") + spec + "': no " + kind + " '" + what +
                   "' (a name or 1.." + std::to_string(names.size()) + ")");
}

/// `option`'s value `spec` as key=value items, in order. UsageError for an item without '='.
std::vector<std::pair<std::string, std::string>> keyValues(const std::string& option,
                                                           const std::string& spec) {
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t start = 0;;) {
    const std::size_t comma = spec.find(',', start);
    const std::string item = spec.substr(start, comma == std::string::npos ? comma : comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw UsageError("--" + option + " '" + spec + "': expected key=value, not '" + item + "'");
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

/// A finite number in `option`'s item `key`. UsageError otherwise.
double keyNumber(const std::string& option, const std::string& spec, const std::string& key,
                 const std::string& text) {
  double x = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), x);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(x))
    throw UsageError("--" + option + " '" + spec + "': " + key + " is not a number: '" + text +
                     "'");
  return x;
}

Pauses parsePauses(const std::string& spec) {
  Pauses p;
  for (const auto& [key, value] : keyValues("pauses", spec)) {
    if (key == "move")
      p.move = keyNumber("pauses", spec, key, value);
    else if (key == "hold")
      p.hold = keyNumber("pauses", spec, key, value);
    else if (key == "ramp")
      p.ramp = keyNumber("pauses", spec, key, value);
    else
      throw UsageError("--pauses '" + spec + "': unknown key '" + key + "' (move, hold, ramp)");
  }
  if (const std::string why = p.problem(); !why.empty())
    throw UsageError("--pauses '" + spec + "': " + why);
  return p;
}

Disturbance parseDisturbance(const std::string& spec, const Model& robot) {
  Disturbance d;
  bool at = false, duration = false;
  const auto number = [&](const std::string& key, const std::string& text) {
    return keyNumber("disturbance", spec, key, text);
  };
  const auto vector3 = [&](const std::string& key, const std::string& text) {
    Eigen::Vector3d v;
    std::size_t start = 0;
    for (int c = 0; c < 3; ++c) {
      const std::size_t colon = text.find(':', start);
      if ((c < 2) == (colon == std::string::npos))
        throw UsageError("--disturbance '" + spec + "': " + key + " takes x:y:z");
      v[c] = number(
          key, text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
      start = colon + 1;
    }
    return v;
  };
  for (const auto& [key, value] : keyValues("disturbance", spec)) {
    if (key == "joint")
      d.joint = namedIndex(value, robot.joint_names, "joint", spec);
    else if (key == "link")
      d.link = namedIndex(value, robot.link_names, "link", spec);
    else if (key == "torque")
      d.torque = number(key, value);
    else if (key == "force")
      d.force = vector3(key, value);
    else if (key == "moment")
      d.moment = vector3(key, value);
    else if (key == "at")
      d.start = number(key, value), at = true;
    else if (key == "for")
      d.duration = number(key, value), duration = true;
    else
      throw UsageError("--disturbance '" + spec + "': unknown key '" + key +
                       "' (joint, torque, link, force, moment, at, for)");
  }
  if ((d.joint >= 0) == (d.link >= 0))
    throw UsageError("--disturbance '" + spec + "': give joint=... or link=..., one of them");
  if (!at || !duration)
    throw UsageError("--disturbance '" + spec + "': give its start at=S and duration for=D [s]");
  if (d.joint >= 0 && (!d.force.isZero() || !d.moment.isZero()))
    throw UsageError("--disturbance '" + spec + "': force and moment go with link=, not joint=");
  if (d.link >= 0 && d.torque != 0.0)
    throw UsageError("--disturbance '" + spec + "': torque goes with joint=, not link=");
  return d;
}

std::string truthPath(const po::variables_map& vm, const std::string& out) {
  if (vm.count("truth-out")) return vm["truth-out"].as<std::string>();
  const std::string stem = out.size() > 4 && out.compare(out.size() - 4, 4, ".csv") == 0
                               ? out.substr(0, out.size() - 4)
                               : out;
  return stem + ".truth.csv";
}
/// The summary (to standard error when standard output carries a file) and, with disturbances,
/// the applied external torques beside the dataset.
void summarizeAndWriteTruth(const po::variables_map& vm, const SimulateRequest& request,
                            const SimulateOutcome& outcome, const std::string& out) {
  const bool piped =
      out == "-" || (vm.count("truth-out") && vm["truth-out"].as<std::string>() == "-");
  std::ostream& summary = piped ? std::cerr : std::cout;
  summary << cliText(simulateSummary(request.robot, outcome, out == "-" ? "standard output" : out));
  // Piped (--out -) without --truth-out: the samples go on (to `dynid monitor --data -`), the
  // ground truth is not written, and the summary says how to have it.
  if (!request.disturbances.empty() && out == "-" && !vm.count("truth-out")) {
    summary << "the applied external torques were not written (--truth-out FILE writes them)\n";
  } else if (!request.disturbances.empty()) {
    const std::string truth = truthPath(vm, out);
    writeExternalTorqueCsv(truth, outcome.trajectory.time, outcome.external);
    summary << "wrote the applied external torques to " << truth << "\n";
  }
}

/// The fixed-base simulate's options as the request (usage errors naming the flag).
SimulateRequest simulateRequest(const po::variables_map& vm) {
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
  sim.stiction = vm["stiction"].as<bool>();
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
    request.one_period = vm["duration"].defaulted();
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
  if (vm.count("pauses")) request.pauses = parsePauses(vm["pauses"].as<std::string>());
  if (vm.count("disturbance"))
    for (const std::string& spec : vm["disturbance"].as<std::vector<std::string>>())
      request.disturbances.push_back(parseDisturbance(spec, request.robot));
  refuseUnused(vm, !request.disturbances.empty(), {"truth-out"}, "applies with --disturbance");
  return request;
}
}  // namespace

int runSimulate(const std::vector<std::string>& args) {
  po::options_description options("dynid simulate");
  addRobotOptions(options);
  addSimulateOptions(options);
  addThreadsOption(options);  // the dataset's rows are formatted on them
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid simulate --robot R [options] --out FILE.csv\n       dynid simulate "
                        "--robot R.urdf --floating-base [--contacts L1,L2:frame] [--motion M] "
                        "[--samples N | --motion-from D.csv | --trajectory E.json [--stand-tilts "
                        "R1,P1,...] | --stance Q1,...,Qn [--sway M] [--turn R]] [--noise-tau S] "
                        "[--noise-force S] "
                        "[--friction-cone MU "
                        "[--sole L,W|X1,Y1,...]] --out FILE.csv",
                        vm))
    return kExitOk;
  if (vm["floating-base"].as<bool>()) return runFloatingSimulate(vm);
  refuseFloatingOptions(vm, {"contacts", "sensors", "motion", "samples", "noise-force",
                             "noise-moment", "friction-cone", "sole", "stand-tilts", "motion-from",
                             "stance", "sway", "turn", "sway-period"});
  const SimulateRequest request = simulateRequest(vm);
  const std::string out = vm["out"].as<std::string>();
  if (out == "-" && vm.count("truth-out") && vm["truth-out"].as<std::string>() == "-")
    throw UsageError("--out and --truth-out cannot both be - (standard output)");
  const SimulateOutcome outcome = simulateRun(request);
  printWarnings(outcome.warnings);
  {
    ThreadPool pool(threadsOption(vm));
    writeDatasetCsv(out, outcome.trajectory, &pool);
  }
  summarizeAndWriteTruth(vm, request, outcome, out);
  return kExitOk;
}

}  // namespace dynid::cli
