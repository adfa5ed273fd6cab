// dynid simulate --floating-base (docs/FLOATING.md): random states, a design on a stand, a given
// motion or a standing sway, with the joint torques and contact wrenches inverse dynamics needs.
#include <cmath>
#include <iostream>
#include <memory>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/simulate.hpp"
#include "analysis/floating/standing.hpp"
#include "analysis/records/excitation_record.hpp"
#include "cli/command_floating.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "data/floating/floating_dataset.hpp"
#include "reports/floating_report.hpp"

namespace dynid::cli {

namespace {
/// --stand-tilts: R1,P1[,R2,P2,...] [rad], pairs of roll and pitch.
std::vector<Eigen::Vector2d> standTiltsOption(const po::variables_map& vm) {
  const std::vector<double> v = parseList(vm["stand-tilts"].as<std::string>(), "stand-tilts");
  if (v.empty() || v.size() % 2 != 0)
    throw UsageError("--stand-tilts takes pairs of roll and pitch [rad], R1,P1[,R2,P2,...], not " +
                     std::to_string(v.size()) + " numbers");
  std::vector<Eigen::Vector2d> tilts;
  for (std::size_t k = 0; k < v.size(); k += 2) tilts.emplace_back(v[k], v[k + 1]);
  return tilts;
}

/// "(0, 0), (-0.4, 0.4)": (roll, pitch) pairs.
std::string standTiltsText(const std::vector<Eigen::Vector2d>& tilts) {
  std::string out;
  for (std::size_t k = 0; k < tilts.size(); ++k)
    out += (k ? ", (" : "(") + formatNumber(tilts[k][0], 4) + ", " + formatNumber(tilts[k][1], 4) +
           ")";
  return out;
}

/// --stance (with --sway, --turn, --sway-period, --samples, --rate, --seed): the standing sway
/// dynid generates, as the motion to simulate along (UsageError for a request out of range or
/// beside another motion; InputError, a data error, when the legs cannot follow it).
std::shared_ptr<const FloatingDataset> standingOption(const po::variables_map& vm,
                                                      const FloatingModel& model,
                                                      const std::vector<Contact>& contacts) {
  if (vm.count("trajectory") || vm.count("motion-from"))
    throw UsageError("--stance generates the motion: not with --trajectory or --motion-from");
  if (contacts.empty())
    throw UsageError("--stance needs --contacts (the feet that stay where the stance puts them)");
  StandingMotionRequest request;
  request.contacts = contacts;
  const std::vector<double> stance = parseList(vm["stance"].as<std::string>(), "stance");
  request.stance =
      Eigen::Map<const Eigen::VectorXd>(stance.data(), static_cast<Eigen::Index>(stance.size()));
  if (request.stance.size() != model.numJoints())
    throw UsageError("--stance has " + std::to_string(request.stance.size()) +
                     " joints, the robot " + std::to_string(model.numJoints()));
  request.sway = vm["sway"].as<double>();
  request.turn = vm["turn"].as<double>();
  request.period = vm["sway-period"].as<double>();
  if (!vm["rate"].defaulted()) request.rate = vm["rate"].as<double>();
  if (vm.count("samples")) request.samples = vm["samples"].as<int>();
  request.seed = vm["seed"].as<std::uint64_t>();
  try {
    request.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  return standingMotion(model, request);
}

/// --trajectory of a standing design (excite --floating-base --stance): its sway over the stance
/// and feet it was made for (--contacts, when given, must be those), one period at --rate
/// unless --samples says otherwise.
std::shared_ptr<const FloatingDataset> standingDesignOption(const po::variables_map& vm,
                                                            const FloatingModel& model,
                                                            const StandingDesignRecord& design,
                                                            std::vector<Contact>& contacts) {
  if (vm.count("stance") || vm.count("motion-from"))
    throw UsageError("--trajectory is a standing design: not with --stance or --motion-from");
  if (vm.count("contacts") && nameListOption(vm, "contacts") != design.contacts) {
    std::string names;
    for (const std::string& c : design.contacts) names += (names.empty() ? "" : ",") + c;
    throw UsageError("--contacts: " + vm["trajectory"].as<std::string>() +
                     " is a standing design for the feet " + names + " (leave --contacts out)");
  }
  StandingMotionRequest request;
  try {
    request = standingDesignRequest(
        model, design, given(vm, "rate") ? vm["rate"].as<double>() : StandingMotionRequest{}.rate,
        vm.count("samples") ? vm["samples"].as<int>() : 0);
    request.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  contacts = request.contacts;
  return standingMotion(model, request);
}

/// simulate --floating-base's options as the library's (UsageError for --samples beside
/// --motion-from and a --sole that is neither a size nor corners).
FloatingSimulationOptions simulationOptions(const po::variables_map& vm,
                                            const FloatingModel& model) {
  FloatingSimulationOptions options;
  options.contacts = contactsOf(model, nameListOption(vm, "contacts"));
  std::optional<FloatingMotion> motion;
  std::vector<SensorSet> unused;
  readSetsAndMotion(vm, unused, motion);
  std::vector<Eigen::Vector2d> design_tilts;  // the stand orientations excite chose, if any
  if (vm.count("trajectory")) {
    ExcitationDesignFile file =
        readExcitationDesignFile(vm["trajectory"].as<std::string>(), model.numJoints());
    if (file.standing) {
      options.motion_from = standingDesignOption(vm, model, *file.standing, options.contacts);
    } else {
      if (given(vm, "rate"))
        throw UsageError("--rate applies to --stance or a standing design's --trajectory");
      options.trajectory = std::move(file.design);
      design_tilts = std::move(file.stand_tilts);
    }
  }
  if (vm.count("motion-from")) {
    if (vm.count("samples"))
      throw UsageError("--samples does not apply to --motion-from (its samples are the file's)");
    options.motion_from = std::make_shared<const FloatingDataset>(
        readFloatingDataset(vm["motion-from"].as<std::string>(), model));
  }
  if (vm.count("stance")) options.motion_from = standingOption(vm, model, options.contacts);
  options.motion = motion.value_or(options.trajectory ? FloatingMotion::kSuspended
                                   : options.contacts.empty() && !options.motion_from
                                       ? FloatingMotion::kFree
                                       : FloatingMotion::kHolding);
  options.samples = options.motion_from   ? options.motion_from->numSamples()
                    : vm.count("samples") ? vm["samples"].as<int>()
                                          : 200;
  options.seed = vm["seed"].as<std::uint64_t>();
  options.torque_noise = vm["noise-tau"].as<double>();
  options.force_noise = vm["noise-force"].as<double>();
  options.moment_noise = vm["noise-moment"].as<double>();
  options.friction_cone = vm["friction-cone"].as<double>();
  if (vm.count("sole")) options.sole = soleOption(vm);
  options.stand_tilts = vm.count("stand-tilts") ? standTiltsOption(vm) : design_tilts;
  return options;
}
}  // namespace

int runFloatingSimulate(const po::variables_map& vm) {
  refuseOutside(vm,
                {"out", "contacts", "motion", "samples", "seed", "noise-tau", "noise-force",
                 "noise-moment", "threads", "trajectory", "friction-cone", "sole", "stand-tilts",
                 "motion-from", "stance", "sway", "turn", "sway-period", "rate"},
                "simulate");
  refuseUnused(vm, vm.count("stance") > 0, {"sway", "turn", "sway-period"}, "applies to --stance");
  if (given(vm, "rate") && !vm.count("stance") && !vm.count("trajectory"))
    throw UsageError("--rate applies to --stance or a standing design's --trajectory");
  const FloatingModel model = loadFloating(vm);
  const FloatingSimulationOptions options = simulationOptions(vm, model);
  const std::string out = vm["out"].as<std::string>();
  FloatingDataset dataset;
  int drawn = 0;
  std::vector<int> outside, unsupported;
  try {
    dataset = simulateFloatingDataset(model, options, &drawn, &outside, &unsupported);
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  writeFloatingDataset(out, dataset);
  const std::string motion_file = vm.count("motion-from") ? vm["motion-from"].as<std::string>()
                                  : vm.count("stance")    ? "a standing sway over the stance"
                                  : options.motion_from
                                      ? "the standing sway of " + vm["trajectory"].as<std::string>()
                                      : "";
  std::ostream& console = out == "-" ? std::cerr : std::cout;
  console << floatingSimulationSummary(model, options, dataset, drawn, motion_file, out);
  if (!vm.count("stand-tilts") && !options.stand_tilts.empty())
    console << "  the stand orientations the design chose (" << vm["trajectory"].as<std::string>()
            << "'s `stand`; --stand-tilts overrides them): " << standTiltsText(options.stand_tilts)
            << " rad\n";
  std::cout.flush();  // the summary before the warnings, wherever both streams go
  std::vector<std::string> warnings = givenMotionWarnings(dataset, outside, unsupported);
  cliTexts(warnings);
  printWarnings(warnings, "dynid simulate: warning: ");
  return kExitOk;
}

}  // namespace dynid::cli
