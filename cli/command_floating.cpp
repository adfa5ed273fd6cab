// The floating-base branches of identifiability, identify, prepare and simulate (--floating-base):
// the floating wing's front end (analysis/floating/, docs/FLOATING.md).
#include "cli/command_floating.hpp"

#include <iostream>
#include <set>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/identify.hpp"
#include "analysis/floating/payload.hpp"
#include "analysis/floating/prepare.hpp"
#include "analysis/floating/simulate.hpp"
#include "analysis/records/excitation_record.hpp"
#include "analysis/records/provenance.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "data/floating/floating_dataset.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/robots.hpp"
#include "reports/floating_identification_report.hpp"
#include "reports/floating_prepare_report.hpp"
#include "reports/floating_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

void refuseOutside(const po::variables_map& vm, const std::set<std::string>& read,
                   const char* command) {
  static const std::set<std::string> robot = {"robot", "drives", "drive-terms", "strict",
                                              "floating-base"};
  for (const auto& [name, value] : vm)
    if (!value.defaulted() && !read.count(name) && !robot.count(name))
      throw UsageError("--" + name + " does not apply to " + command +
                       " --floating-base (docs/FLOATING.md)");
}

FloatingModel loadFloating(const po::variables_map& vm) {
  std::vector<std::string> warnings;
  FloatingModel model =
      loadFloatingRobot(vm["robot"].as<std::string>(), robotOptions(vm), &warnings);
  printWarnings(warnings);
  return model;
}

/// --sensors and --motion as the request's; usage errors naming the flag.
void readSetsAndMotion(const po::variables_map& vm, std::vector<SensorSet>& sensors,
                       std::optional<FloatingMotion>& motion) {
  try {
    for (const std::string& name : nameListOption(vm, "sensors"))
      sensors.push_back(parseSensorSet(name));
    if (vm.count("motion")) motion = parseFloatingMotion(vm["motion"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
}

/// --sole: LENGTH,WIDTH (a rectangle centred at the frame) or X1,Y1,X2,Y2,X3,Y3[,...] (corners).
std::vector<Eigen::Vector2d> soleOption(const po::variables_map& vm) {
  const std::vector<double> v = parseList(vm["sole"].as<std::string>(), "sole");
  if (v.size() == 2) {
    try {
      return rectangularSole(v[0], v[1]);
    } catch (const InputError& e) {
      throw UsageError(cliText(e.what()));
    }
  }
  if (v.size() < 6 || v.size() % 2 != 0)
    throw UsageError(
        "--sole takes LENGTH,WIDTH [m] (a rectangle centred at the frame) or the corners "
        "X1,Y1,X2,Y2,X3,Y3[,...] [m] in the frame's x-y plane, not " +
        std::to_string(v.size()) + " numbers");
  std::vector<Eigen::Vector2d> corners;
  for (std::size_t k = 0; k < v.size(); k += 2) corners.emplace_back(v[k], v[k + 1]);
  return corners;
}

void addFloatingOptions(po::options_description& options, const std::string& does) {
  options.add_options()(
      "floating-base", po::bool_switch(),
      ("the robot (a URDF) floats: a free-flyer joint at its root; " + does).c_str())(
      "contacts", po::value<std::string>(),
      "with --floating-base: the links that touch the world, comma-separated, each NAME (a point "
      "force), NAME:point or NAME:frame (a wrench, a flat foot)")(
      "sensors", po::value<std::string>(),
      "with --floating-base: wrenches, torques_wrenches, torques_contacts (comma-separated; "
      "default all)")(
      "motion", po::value<std::string>(),
      "with --floating-base: holding (contacts hold; the default with --contacts), free (nothing "
      "holds; the default without), suspended (the base held still) or carried (the base moved "
      "by its support: a mobile platform, a motion stand); identify's default for data with a "
      "contact on the base: carried when the base moves in the data, else suspended");
}

void refuseFloatingOptions(const po::variables_map& vm,
                           std::initializer_list<const char*> options) {
  for (const char* option : options)
    if (vm.count(option) && !vm[option].defaulted())
      throw UsageError(std::string("--") + option + " needs --floating-base");
}

int runFloatingIdentifiability(const po::variables_map& vm) {
  if (vm.count("data"))
    throw UsageError(
        "--data with --floating-base: a floating-base dataset's excitation is not "
        "measured yet; the analysis is structural (docs/FLOATING.md)");
  FloatingIdentifiabilityRequest request;
  request.structural = structuralOptions(vm);
  request.contacts = nameListOption(vm, "contacts");
  readSetsAndMotion(vm, request.sensors, request.motion);
  const FloatingModel model = loadFloating(vm);
  const FloatingIdentifiabilityOutcome outcome = floatingIdentifiabilityRun(model, request);
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(
      dir, {{"floating_identifiability.json",
             jsonText(withProvenance(floatingIdentifiabilityJson(model, outcome)), 2) + "\n"},
            {"floating_identifiability.md", floatingIdentifiabilityMarkdown(model, outcome)}});
  for (const SensorSetBase& s : outcome.sets)
    if (s.base.rankGap() < 1e4)
      std::cerr << "warning: " << sensorSetName(s.set) << ": the rank gap is only "
                << formatNumber(s.base.rankGap(), 4)
                << " (below 1e4): a close call; try more --samples\n";
  std::cout << floatingIdentifiabilitySummary(model, outcome, dir);
  return kExitOk;
}

namespace {
/// identify --floating-base's options as the library's request, checked (usage errors naming
/// the flag).
FloatingIdentifyRequest floatingIdentifyRequest(const po::variables_map& vm) {
  refuseOutside(vm,
                {"method",
                 "data",
                 "validate",
                 "out",
                 "contacts",
                 "sensors",
                 "motion",
                 "samples",
                 "seed",
                 "tolerance",
                 "threads",
                 "payload-link",
                 "prior-weight",
                 "unloaded",
                 "horizon",
                 "segments",
                 "combined-weight",
                 "no-gc-floor",
                 "combined-seconds",
                 "combined-iterations"},
                "identify");
  if (!vm.count("data")) throw UsageError("--floating-base needs --data (a floating dataset)");
  if (!vm.count("robot")) throw UsageError("--floating-base needs --robot (its URDF)");
  FloatingIdentifyRequest request;
  try {
    if (!vm["method"].defaulted())  // ols or wls; the request's default (wls) otherwise
      request.method = parseFloatingMethod(vm["method"].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  const bool combined = request.method == FloatingMethod::kCombined;
  if (!vm["prior-weight"].defaulted() && request.method != FloatingMethod::kPc && !combined)
    throw UsageError("--prior-weight applies to --method pc or combined");
  request.prior_weight = priorWeightOption(vm);
  refuseUnused(vm, combined,
               {"combined-weight", "no-gc-floor", "combined-seconds", "combined-iterations"},
               "applies to --method combined");
  request.combined.gc_weight = vm["combined-weight"].as<double>();
  request.combined.noise_floor = !vm["no-gc-floor"].as<bool>();
  request.combined.max_seconds = vm["combined-seconds"].as<double>();
  request.combined.max_iterations = vm["combined-iterations"].as<int>();
  request.threads = threadsOption(vm);
  request.structural = structuralOptions(vm);
  request.contacts = nameListOption(vm, "contacts");
  readSetsAndMotion(vm, request.sensors, request.motion);
  request.gc->horizon = vm["horizon"].as<double>();
  request.gc->num_segments = vm["segments"].as<int>();
  try {
    request.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  return request;
}
}  // namespace

int runFloatingIdentify(const po::variables_map& vm) {
  FloatingIdentifyRequest request = floatingIdentifyRequest(vm);
  const bool combined = request.method == FloatingMethod::kCombined;
  if (stderrIsTerminal())
    request.combined.control.progress = [](const std::string& line) {
      std::cerr << "[identify] " << line << "\n";
    };
  // combined stops at its next rollout on Ctrl-C, keeping its best so far (as the fixed base's).
  std::optional<InterruptGuard> guard;
  if (combined) request.combined.control.stop = guard.emplace().flag();
  const FloatingModel model = loadFloating(vm);
  FloatingDataSources sources{vm["data"].as<std::string>(), "", {}, ""};
  const FloatingDataset data = readFloatingDataset(sources.data, model);
  std::optional<FloatingDataset> validation;
  if (vm.count("validate")) {
    sources.validation = vm["validate"].as<std::string>();
    validation = readFloatingDataset(sources.validation, model);
  }
  FloatingIdentifyOutcome outcome =
      floatingIdentifyRun(model, request, data, validation ? &*validation : nullptr);
  cliTexts(outcome.warnings);
  outcome.gc.refused = cliText(outcome.gc.refused);
  outcome.gc.validation_refused = cliText(outcome.gc.validation_refused);
  printWarnings(outcome.warnings, "dynid identify: warning: ");
  if (vm.count("unloaded") && !vm.count("payload-link"))
    throw UsageError("--unloaded needs --payload-link (the link the payload is fixed to)");
  if (vm.count("unloaded")) {
    sources.unloaded = vm["unloaded"].as<std::string>();
    const FloatingIdentifyOutcome unloaded = floatingIdentifyRun(
        model, pairedRequest(request, outcome), readFloatingDataset(sources.unloaded, model));
    sources.payloads =
        floatingPayloadsFromPair(model, outcome, unloaded, vm["payload-link"].as<std::string>());
  } else if (vm.count("payload-link")) {
    sources.payloads = floatingPayloads(model, outcome, data, vm["payload-link"].as<std::string>());
  }
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(
      dir,
      {{"floating_identification.json",
        jsonText(withProvenance(floatingIdentificationJson(model, outcome, sources)), 2) + "\n"},
       {"floating_identification.md", floatingIdentificationMarkdown(model, outcome, sources)}});
  std::cout << cliText(floatingIdentificationSummary(model, outcome, sources, dir));
  if (guard) return exitAfter(*guard, "identify", "the combined estimates are their best so far");
  return kExitOk;
}

int runFloatingPrepare(const po::variables_map& vm) {
  refuseOutside(vm,
                {"log", "out", "topic", "imu-topic", "wrench-topics", "stamp", "rate", "cutoff",
                 "order", "max-gap", "trim", "threads", "contact-threshold", "contact-topics"},
                "prepare");
  if (!vm.count("robot")) throw UsageError("--floating-base needs --robot (its URDF)");
  const auto logs =
      vm.count("log") ? vm["log"].as<std::vector<std::string>>() : std::vector<std::string>{};
  if (logs.size() != 1)
    throw UsageError(
        "--floating-base needs --log with one recording (.mcap, .db3, .bag, a bag "
        "directory)");
  FloatingLogTopics topics;
  if (vm.count("topic")) topics.joint_topic = vm["topic"].as<std::string>();
  if (vm.count("imu-topic")) topics.imu_topic = vm["imu-topic"].as<std::string>();
  topics.wrench_topics = nameListOption(vm, "wrench-topics");
  for (const std::string& pair : nameListOption(vm, "contact-topics")) {
    const std::size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size())
      throw UsageError("--contact-topics takes TOPIC=FRAME pairs, comma-separated, not '" + pair +
                       "'");
    if (!topics.contact_topics.emplace(pair.substr(0, eq), pair.substr(eq + 1)).second)
      throw UsageError("--contact-topics names " + pair.substr(0, eq) + " twice");
  }
  FloatingPrepareOptions options;
  options.rate = vm["rate"].as<double>();
  const std::string cutoff = vm["cutoff"].as<std::string>();
  if (cutoff == "auto")
    throw UsageError(
        "--cutoff auto (from q's spectrum) does not apply to prepare --floating-base: "
        "give a frequency [Hz], 0 (none) or default");
  if (cutoff != "default") {
    const std::vector<double> value = parseList(cutoff, "cutoff");
    if (value.size() != 1 || !(value[0] >= 0.0))
      throw UsageError(
          "--cutoff with --floating-base must be a frequency >= 0 [Hz] or default, "
          "not '" +
          cutoff + "'");
    options.cutoff = value[0];
  }
  options.order = vm["order"].as<int>();
  options.max_gap = vm["max-gap"].as<double>();
  options.trim = vm["trim"].as<double>();
  options.receive_time = receiveTimeOption(vm);
  options.contact_threshold = vm["contact-threshold"].as<double>();
  try {
    options.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  std::vector<std::string> warnings;  // prepare reads the robot's joints and frames, not its mass
  const FloatingModel model = loadFloatingRobot(vm["robot"].as<std::string>(), {}, &warnings);
  printWarnings(warnings);
  FloatingPrepareOutcome outcome = prepareFloatingLog(model, logs.front(), topics, options);
  cliTexts(outcome.warnings);
  printWarnings(outcome.warnings, "dynid prepare: warning: ");
  const std::string dir = vm["out"].as<std::string>();
  OutputSet files(dir);
  writeFloatingDataset(files.stream("floating_dataset.csv"), outcome.dataset);
  files.add("floating_prepare.json",
            jsonText(withProvenance(floatingPrepareJson(model, logs.front(), outcome)), 2) + "\n");
  files.publish();
  std::cout << cliText(floatingPrepareSummary(model, outcome, dir + "/floating_dataset.csv",
                                              dir + "/floating_prepare.json"));
  return kExitOk;
}

}  // namespace dynid::cli
