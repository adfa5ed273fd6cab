// The floating wing: what each sensor set of a floating-base robot determines
// (analysis/floating/identifiability.hpp, `dynid identifiability --floating-base`), simulated
// floating datasets (simulate.hpp), datasets prepared from recordings (prepare.hpp) and the
// estimate on them (identify.hpp), documents as dicts.
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "analysis/floating/gc_data.hpp"
#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/identify.hpp"
#include "analysis/floating/payload.hpp"
#include "analysis/floating/prepare.hpp"
#include "analysis/floating/simulate.hpp"
#include "analysis/floating/standing.hpp"
#include "analysis/records/excitation_record.hpp"
#include "data/robots.hpp"
#include "python/run_support.hpp"
#include "reports/floating_identification_report.hpp"
#include "reports/floating_prepare_report.hpp"
#include "reports/floating_report.hpp"

namespace dynid::python {

FloatingModel floatingRobot(const PathLike& robot, const TermsLike& drive_terms) {
  RobotOptions options;
  if (!drive_terms.is_none()) options.drive_terms = driveTermsArg(drive_terms, "drive_terms");
  return loadFloatingRobot(pathArg(robot, "robot"), options);
}

/// sole=(length, width) [m], a rectangle centred at the frame, or [(x, y), ...] [m], its corners.
std::vector<Eigen::Vector2d> soleOf(const py::object& sole) {
  const InputError bad("`sole` is (length, width) [m] or a sequence of corners (x, y) [m]");
  const auto number = [&](py::handle h) {
    try {
      return h.cast<double>();
    } catch (const py::cast_error&) {
      throw bad;
    }
  };
  const auto sequence = [](py::handle h) {
    return py::isinstance<py::sequence>(h) && !py::isinstance<py::str>(h);
  };
  if (!sequence(sole)) throw bad;
  const py::sequence items = sole.cast<py::sequence>();
  if (items.size() == 2 && !sequence(items[0]) && !sequence(items[1]))
    return rectangularSole(number(items[0]), number(items[1]));
  std::vector<Eigen::Vector2d> corners;
  for (py::handle item : items) {
    if (!sequence(item) || py::len(item) != 2) throw bad;
    const py::sequence xy = py::reinterpret_borrow<py::sequence>(item);
    corners.emplace_back(number(xy[0]), number(xy[1]));
  }
  return corners;
}

namespace {

py::object floatingIdentifiability(const PathLike& robot,
                                   const std::optional<std::vector<std::string>>& contacts,
                                   const std::optional<std::vector<std::string>>& sensors,
                                   const std::optional<std::string>& motion,
                                   const TermsLike& drive_terms, int samples, std::uint64_t seed) {
  FloatingIdentifiabilityRequest request;
  request.contacts = contacts.value_or(std::vector<std::string>{});
  for (const std::string& name : sensors.value_or(std::vector<std::string>{}))
    request.sensors.push_back(parseSensorSet(name));
  request.motion = motion                     ? parseFloatingMotion(*motion)
                   : request.contacts.empty() ? FloatingMotion::kFree
                                              : FloatingMotion::kHolding;
  request.structural.samples = samples;
  request.structural.seed = seed;
  RobotOptions options;
  if (!drive_terms.is_none()) options.drive_terms = driveTermsArg(drive_terms, "drive_terms");
  const FloatingModel model = loadFloatingRobot(pathArg(robot, "robot"), options);
  FloatingIdentifiabilityOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = floatingIdentifiabilityRun(model, request);
  }
  return parsedJson(floatingIdentifiabilityJson(model, outcome));
}

py::object floatingIdentify(const PathLike& robot, const PathLike& data,
                            const OptionalPathLike& validate,
                            const std::optional<std::vector<std::string>>& contacts,
                            const std::optional<std::vector<std::string>>& sensors,
                            const std::optional<std::string>& motion, const std::string& method,
                            const TermsLike& drive_terms, int samples, std::uint64_t seed,
                            const std::optional<std::string>& payload_link, double prior_weight,
                            const OptionalPathLike& unloaded, double horizon, int num_segments,
                            std::optional<double> combined_weight,
                            std::optional<double> combined_seconds,
                            std::optional<int> combined_iterations, int threads) {
  FloatingIdentifyRequest request;
  // The combined estimator's options, as identify --floating-base's --combined-weight,
  // --combined-seconds and --combined-iterations (checked by floatingIdentifyRun).
  if (method != "combined" && (combined_weight || combined_seconds || combined_iterations))
    throw py::value_error("combined_* apply to method 'combined', not '" + method + "'");
  if (combined_weight) request.combined.gc_weight = *combined_weight;
  if (combined_seconds) request.combined.max_seconds = *combined_seconds;
  if (combined_iterations) request.combined.max_iterations = *combined_iterations;
  request.threads = threads;
  request.prior_weight = prior_weight;
  request.gc = FloatingGcOptions{horizon, num_segments};
  request.contacts = contacts.value_or(std::vector<std::string>{});
  for (const std::string& name : sensors.value_or(std::vector<std::string>{}))
    request.sensors.push_back(parseSensorSet(name));
  if (motion) request.motion = parseFloatingMotion(*motion);
  request.method = parseFloatingMethod(method);
  request.structural.samples = samples;
  request.structural.seed = seed;
  const FloatingModel model = floatingRobot(robot, drive_terms);
  FloatingDataSources sources{pathArg(data, "data"), "", {}, ""};
  const FloatingDataset training = readFloatingDataset(sources.data, model);
  std::optional<FloatingDataset> held_out;
  if (!validate.is_none()) {
    sources.validation = pathArg(validate, "validate");
    held_out = readFloatingDataset(sources.validation, model);
  }
  if (!unloaded.is_none() && !payload_link)
    throw InputError("`unloaded` needs `payload_link` (the link the payload is fixed to)");
  std::optional<FloatingDataset> unloaded_data;
  if (!unloaded.is_none()) {
    sources.unloaded = pathArg(unloaded, "unloaded");
    unloaded_data = readFloatingDataset(sources.unloaded, model);
  }
  // combined stops at its next rollout on Ctrl-C (KeyboardInterrupt), keeping its best so far.
  Interrupt interrupt;
  request.combined.control.stop = interrupt.flag();
  request.combined.control.on_check = [&] { interrupt.poll(); };
  FloatingIdentifyOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = floatingIdentifyRun(model, request, training, held_out ? &*held_out : nullptr);
    if (unloaded_data)
      sources.payloads = floatingPayloadsFromPair(
          model, outcome,
          floatingIdentifyRun(model, pairedRequest(request, outcome), *unloaded_data),
          *payload_link);
    else if (payload_link)
      sources.payloads = floatingPayloads(model, outcome, training, *payload_link);
  }
  pythonTexts(outcome.warnings);
  outcome.gc.refused = pythonText(outcome.gc.refused);
  outcome.gc.validation_refused = pythonText(outcome.gc.validation_refused);
  warnAll(outcome.warnings);
  interrupt.warnIfStopped();
  return parsedJson(floatingIdentificationJson(model, outcome, sources));
}

py::dict floatingGcErrorOf(const PathLike& robot, const PathLike& data,
                           const std::optional<std::vector<std::string>>& contacts, double horizon,
                           int num_segments, int substeps, const TermsLike& drive_terms) {
  const FloatingModel model = floatingRobot(robot, drive_terms);
  const FloatingDataset dataset = readFloatingDataset(pathArg(data, "data"), model);
  const FloatingGcData recording =
      floatingGcData(model, dataset, contacts.value_or(std::vector<std::string>{}));
  FloatingGcResult result;
  {
    py::gil_scoped_release release;
    result = floatingGcError(model, recording, {horizon, num_segments, substeps});
  }
  py::dict out;
  out["error"] = result.error;
  out["segment_errors"] = toNumpy(result.segment_errors);
  out["starts"] = result.starts;
  out["samples_per_segment"] = result.samples_per_segment;
  out["horizon"] = result.horizon;
  return out;
}

/// A standing design's sway (excite_standing) over its stance and feet (`contacts`, when given,
/// must be those; `feet` set to them), one period at `rate` unless `samples` says otherwise.
std::shared_ptr<const FloatingDataset> standingDesignMotion(
    const FloatingModel& model, const StandingDesignRecord& design,
    const std::optional<std::vector<std::string>>& contacts, double rate,
    const std::optional<int>& samples, std::vector<Contact>& feet) {
  if (contacts && *contacts != design.contacts)
    throw py::value_error(
        "contacts: the trajectory is a standing design for other feet (leave "
        "contacts out)");
  const StandingMotionRequest request =
      standingDesignRequest(model, design, rate, samples.value_or(0));
  feet = request.contacts;
  return standingMotion(model, request);
}

std::string simulateFloatingTo(const PathLike& robot, const PathLike& out,
                               const std::optional<std::vector<std::string>>& contacts,
                               const std::optional<std::string>& motion,
                               const std::optional<int>& samples, std::uint64_t seed,
                               double noise_tau, double noise_force, double noise_moment,
                               const TermsLike& drive_terms, const OptionalPathLike& trajectory,
                               double friction_cone, const SoleLike& sole,
                               const OptionalPathLike& motion_from,
                               const std::optional<std::vector<std::pair<double, double>>>& tilts,
                               const std::optional<std::vector<double>>& stance, double sway,
                               double turn, double sway_period, double rate) {
  const FloatingModel model = floatingRobot(robot, drive_terms);
  FloatingSimulationOptions options;
  options.contacts = contactsOf(model, contacts.value_or(std::vector<std::string>{}));
  std::optional<ExcitationDesignFile> file;
  if (!trajectory.is_none())
    file = readExcitationDesignFile(pathArg(trajectory, "trajectory"), model.numJoints());
  const bool standing_design = file && file->standing;
  const StandingMotionRequest standing_defaults;
  if (!stance && (sway != standing_defaults.sway || turn != standing_defaults.turn ||
                  sway_period != standing_defaults.period))
    throw py::value_error("sway, turn and sway_period apply with stance");
  if (!stance && !standing_design && rate != standing_defaults.rate)
    throw py::value_error("rate applies with stance or a standing design's trajectory");
  if (standing_design && (stance || !motion_from.is_none()))
    throw py::value_error("trajectory is a standing design: not with stance or motion_from");
  if (stance) {  // simulate --stance: the standing sway dynid generates, as the motion
    if (!trajectory.is_none() || !motion_from.is_none())
      throw py::value_error("stance generates the motion: not with trajectory or motion_from");
    StandingMotionRequest request;
    request.contacts = options.contacts;
    request.stance = Eigen::Map<const Eigen::VectorXd>(stance->data(),
                                                       static_cast<Eigen::Index>(stance->size()));
    request.sway = sway;
    request.turn = turn;
    request.period = sway_period;
    request.rate = rate;
    if (samples) request.samples = *samples;
    request.seed = seed;
    options.motion_from = standingMotion(model, request);
  }
  if (standing_design) {
    options.motion_from =
        standingDesignMotion(model, *file->standing, contacts, rate, samples, options.contacts);
  } else if (file) {
    options.trajectory = std::move(file->design);
    if (!tilts) options.stand_tilts = std::move(file->stand_tilts);  // the design's, if it chose
  }
  if (!motion_from.is_none()) {
    if (samples)
      throw InputError("`samples` does not apply to `motion_from` (its samples are the file's)");
    options.motion_from = std::make_shared<const FloatingDataset>(
        readFloatingDataset(pathArg(motion_from, "motion_from"), model));
  }
  options.motion = motion                                             ? parseFloatingMotion(*motion)
                   : options.trajectory                               ? FloatingMotion::kSuspended
                   : options.contacts.empty() && !options.motion_from ? FloatingMotion::kFree
                                                                      : FloatingMotion::kHolding;
  options.samples = options.motion_from ? options.motion_from->numSamples() : samples.value_or(200);
  options.seed = seed;
  options.torque_noise = noise_tau;
  options.force_noise = noise_force;
  options.moment_noise = noise_moment;
  options.friction_cone = friction_cone;
  if (!sole.is_none()) options.sole = soleOf(sole);
  for (const auto& [roll, pitch] : tilts.value_or(std::vector<std::pair<double, double>>{}))
    options.stand_tilts.emplace_back(roll, pitch);
  const std::string path = pathArg(out, "out");
  std::vector<int> outside, unsupported;
  FloatingDataset dataset;
  {
    py::gil_scoped_release release;
    dataset = simulateFloatingDataset(model, options, nullptr, &outside, &unsupported);
    writeFloatingDataset(path, dataset);
  }
  std::vector<std::string> warnings = givenMotionWarnings(dataset, outside, unsupported);
  pythonTexts(warnings);
  warnAll(warnings);
  return path;
}

py::object prepareFloating(
    const PathLike& robot, const PathLike& log, const PathLike& out,
    const std::optional<std::string>& joint_topic, const std::optional<std::string>& imu_topic,
    const std::optional<std::vector<std::string>>& wrench_topics, double rate,
    const std::optional<double>& cutoff, int order, double max_gap,
    const std::optional<double>& trim, const std::string& stamp, const TermsLike& drive_terms,
    double contact_threshold,
    const std::optional<std::map<std::string, std::string>>& contact_topics) {
  const FloatingModel model = floatingRobot(robot, drive_terms);
  FloatingLogTopics topics;
  topics.joint_topic = joint_topic.value_or("");
  topics.imu_topic = imu_topic.value_or("");
  topics.wrench_topics = wrench_topics.value_or(std::vector<std::string>{});
  if (contact_topics) topics.contact_topics = *contact_topics;
  FloatingPrepareOptions options;
  options.rate = rate;
  if (cutoff) options.cutoff = *cutoff;
  options.order = order;
  options.max_gap = max_gap;
  if (trim) options.trim = *trim;
  if (stamp != "header" && stamp != "receive")
    throw InputError("`stamp` must be header or receive, not '" + stamp + "'");
  options.receive_time = stamp == "receive";
  options.contact_threshold = contact_threshold;
  const std::string recording = pathArg(log, "log"), path = pathArg(out, "out");
  FloatingPrepareOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = prepareFloatingLog(model, recording, topics, options);
    writeFloatingDataset(path, outcome.dataset);
  }
  return parsedJson(floatingPrepareJson(model, recording, outcome));
}

/// simulate_floating (`dynid simulate --floating-base`).
void bindSimulateFloating(py::module_& m) {
  m.def("simulate_floating", &simulateFloatingTo, py::arg("robot"), py::arg("out"),
        py::arg("contacts") = py::none(), py::arg("motion") = py::none(),
        py::arg("samples") = py::none(), py::arg("seed") = 1, py::arg("noise_tau") = 0.0,
        py::arg("noise_force") = 0.0, py::arg("noise_moment") = 0.0,
        py::arg("drive_terms") = py::none(), py::arg("trajectory") = py::none(),
        py::arg("friction_cone") = 0.0, py::arg("sole") = py::none(),
        py::arg("motion_from") = py::none(), py::arg("stand_tilts") = py::none(),
        py::arg("stance") = py::none(), py::arg("sway") = StandingMotionRequest{}.sway,
        py::arg("turn") = StandingMotionRequest{}.turn,
        py::arg("sway_period") = StandingMotionRequest{}.period,
        py::arg("rate") = StandingMotionRequest{}.rate,
        "`dynid simulate --floating-base`: a floating dataset of random states of the motion "
        "(holding, the default with contacts; free; suspended; carried: the base moved by its "
        "support, whose wrench is measured) written to `out`, with noise on "
        "the torques, contact forces and moments; with trajectory (an excitation.json of the "
        "robot with its base fixed), `samples` states of that design over one period, the base "
        "held still (with stand_tilts [(roll, pitch), ...] [rad], one period at each stand "
        "orientation in turn, 1 s apart; None: those the design chose, if any); with friction_cone "
        "(mu, holding), the contacts' forces "
        "within friction "
        "cones about the ground's normal, states they cannot hold drawn again; with sole "
        "(length, width) [m] (a rectangle centred at the frame) or its corners [(x, y), ...] "
        "[m] in the frame's x-y plane too, every frame contact's wrench that of its sole's corner "
        "forces within the cones about the sole's normal (its centre of pressure in the "
        "corners' convex hull); "
        "with motion_from (a floating dataset's path), its motion sample by sample instead of "
        "random states, the contacts holding where its flags say; with stance (the joints at "
        "rest [rad], contacts given), a standing sway dynid generates (simulate --stance: the "
        "base sways by `sway` [m] and turns by `turn` [rad] over `sway_period` [s] above "
        "contacts that stay still, the legs following; `samples` at `rate` [Hz]); with a "
        "trajectory that is a standing design (excite_standing's standing_excitation.json), its "
        "sway over its stance and feet, one period at `rate` unless `samples` says. Returns the "
        "path.");
}
}  // namespace

void bindFloating(py::module_& m) {
  bindSimulateFloating(m);
  m.def("prepare_floating", &prepareFloating, py::arg("robot"), py::arg("log"), py::arg("out"),
        py::arg("joint_topic") = py::none(), py::arg("imu_topic") = py::none(),
        py::arg("wrench_topics") = py::none(), py::arg("rate") = 0.0,
        py::arg("cutoff") = py::none(), py::arg("order") = 4, py::arg("max_gap") = 0.0,
        py::arg("trim") = py::none(), py::arg("stamp") = "header",
        py::arg("drive_terms") = py::none(), py::arg("contact_threshold") = 0.0,
        py::arg("contact_topics") = py::none(),
        "`dynid prepare --floating-base`: a floating-base robot (a URDF path) and a recording "
        "(.mcap, .db3, .bag, a bag directory) with JointState, Imu (on the base body) and "
        "WrenchStamped topics (each the only one of its type, or named), resampled to one time "
        "base, low-passed alike (cutoff None: 10 Hz, 0: none) and differentiated, written to "
        "`out` as a floating dataset; with contact_threshold [N], a contact flag per wrench "
        "frame, holding where its force's norm reaches it; contact_topics: std_msgs/Bool "
        "topics as contact flags, {topic: frame}. Returns floating_prepare.json as a "
        "dict (docs/FLOATING.md).");
  m.def("floating_gc_error", &floatingGcErrorOf, py::arg("robot"), py::arg("data"),
        py::arg("contacts") = py::none(), py::arg("horizon") = FloatingGcOptions{}.horizon,
        py::arg("num_segments") = FloatingGcOptions{}.num_segments,
        py::arg("substeps") = FloatingGcOptions{}.substeps, py::arg("drive_terms") = py::none(),
        "The GC error on a floating base (docs/FLOATING.md): segments of a floating dataset "
        "(path) rolled out from their recorded start by the robot's forward dynamics, driven by "
        "its joint torques and the wrenches measured at the contacts, a contact known by its flag "
        "alone held still while it holds (every frame the dataset measures a wrench at or flags "
        "when contacts is None), compared at their end in q, dq, the base "
        "twist and the base's rotation angle. Returns {'error', 'segment_errors', 'starts' (each "
        "segment's first sample), 'samples_per_segment', 'horizon' (the horizon taken to the "
        "nearest whole number of sample periods)}.");
  m.def("floating_identify", &floatingIdentify, py::arg("robot"), py::arg("data"),
        py::arg("validate") = py::none(), py::arg("contacts") = py::none(),
        py::arg("sensors") = py::none(), py::arg("motion") = py::none(), py::arg("method") = "wls",
        py::arg("drive_terms") = py::none(), py::arg("samples") = 0, py::arg("seed") = 1,
        py::arg("payload_link") = py::none(), py::arg("prior_weight") = kDefaultPriorWeight,
        py::arg("unloaded") = py::none(), py::arg("horizon") = FloatingGcOptions{}.horizon,
        py::arg("num_segments") = FloatingGcOptions{}.num_segments,
        py::arg("combined_weight") = py::none(), py::arg("combined_seconds") = py::none(),
        py::arg("combined_iterations") = py::none(), py::arg("threads") = 1,
        "`dynid identify --floating-base`: a floating-base robot (a URDF path) and a floating "
        "dataset (path; validate: a held-out one); each sensor set the data feed estimated by wls "
        "(each channel's noise estimated), ols, pc (weighted as wls, every body physically "
        "consistent, the robot's own parameters the prior at prior_weight) or combined (pc's "
        "estimate refined to predict the data's motion too: the GC error over the segments "
        "below, weighted by combined_weight (1), within combined_iterations (50) and "
        "combined_seconds (60), its rollouts on threads); with payload_link, "
        "the payload fixed to that link as well (the robot read as unloaded; with unloaded, a "
        "dataset of the robot without it, from the two datasets' estimates instead). Returns "
        "floating_identification.json as a dict (docs/FLOATING.md); motion as the CLI's --motion "
        "(unset with a contact on the base: carried when the base moves in the data, else "
        "suspended); each estimate's GC error (and the robot's own) over num_segments segments "
        "of horizon [s] where the data are a motion with every contact's wrench ('gc').");
  m.def("floating_identifiability", &floatingIdentifiability, py::arg("robot"),
        py::arg("contacts") = py::none(), py::arg("sensors") = py::none(),
        py::arg("motion") = py::none(), py::arg("drive_terms") = py::none(), py::arg("samples") = 0,
        py::arg("seed") = 1,
        "`dynid identifiability --floating-base`: a floating-base robot (a URDF path) and its "
        "contacts (link names, each optionally ':point' or ':frame'); what each sensor set "
        "(wrenches, torques_wrenches, torques_contacts; default all) determines in the motion "
        "(holding, the default with contacts; free, without; suspended; carried). Returns "
        "floating_identifiability.json as a dict (docs/FLOATING.md).");
}

}  // namespace dynid::python
