// dynid excite --floating-base --contacts FEET --stance Q (docs/FLOATING.md, "Designing a
// standing sway"): a standing robot's sway designed for identification
// (analysis/floating/standing_design.hpp).
#include <cstdio>
#include <iostream>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/standing_design.hpp"
#include "analysis/records/provenance.hpp"
#include "cli/command_floating.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "data/json_number.hpp"
#include "data/robots.hpp"
#include "reports/output.hpp"
#include "reports/standing_design_report.hpp"

namespace dynid::cli {

void addFloatingExciteOptions(po::options_description& options) {
  const StandingDesignRequest d;  // every default is the request's own
  addFloatingOptions(options,
                     "with --contacts and --stance: design a standing robot's sway instead, the "
                     "base's six coordinates (docs/FLOATING.md)");
  options.add_options()(
      "stance", po::value<std::string>(),
      "with --floating-base and --contacts: the joints at rest, q1,...,qn [rad], the feet "
      "staying where it puts them (defaults then: --period 4, --harmonics 3, --starts 4, "
      "--evaluations 300, --grid-rate 10, --check-rate 100; --sensors names the one set whose "
      "condition number the sway lowers, default torques_contacts)")(
      "max-sway", po::value<double>()->default_value(d.max_sway),
      "with --stance: the base's largest excursion along each world axis [m]")(
      "max-turn", po::value<double>()->default_value(d.max_turn),
      "with --stance: the largest roll, pitch and yaw [rad]")(
      "max-swing", po::value<double>()->default_value(d.max_swing),
      "with --stance: the largest excursion from the stance of each joint no foot depends on (a "
      "humanoid's arms, head and trunk), which the design moves too [rad] (0: they stay)")(
      "joint-margin", po::value<double>()->default_value(d.joint_margin),
      "with --stance: how far the joints stay inside their limits [rad]")(
      "friction-cone", po::value<double>()->default_value(d.friction_cone),
      "with --stance: the feet's friction coefficient, their forces kept within its cones "
      "(0: none)")(
      "sole", po::value<std::string>(),
      "with --stance: a flat sole under every frame contact, LENGTH,WIDTH [m] or its corners "
      "X1,Y1,X2,Y2,X3,Y3[,...] [m] (as simulate's): each centre of pressure kept in it");
}

namespace {

/// The request from the options: the standing defaults where excite's own were not given.
StandingDesignRequest standingRequest(const po::variables_map& vm, const FloatingModel& model) {
  if (!vm.count("stance") || !vm.count("contacts"))
    throw UsageError(
        "excite --floating-base designs a standing robot's sway: it needs --contacts (the feet) "
        "and --stance (the joints at rest); a robot on a stand is designed without "
        "--floating-base (--stands)");
  StandingDesignRequest r;
  try {
    r.contacts = contactsOf(model, nameListOption(vm, "contacts"));
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  const std::vector<double> stance = parseList(vm["stance"].as<std::string>(), "stance");
  r.stance =
      Eigen::Map<const Eigen::VectorXd>(stance.data(), static_cast<Eigen::Index>(stance.size()));
  if (r.stance.size() != model.numJoints())
    throw UsageError("--stance has " + std::to_string(r.stance.size()) + " joints, the robot " +
                     std::to_string(model.numJoints()));
  const std::vector<std::string> sets = nameListOption(vm, "sensors");
  if (sets.size() > 1)
    throw UsageError("--sensors: a standing design lowers one set's condition number, not " +
                     std::to_string(sets.size()) + " (every set is scored)");
  try {
    if (!sets.empty()) r.set = parseSensorSet(sets.front());
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  if (given(vm, "period")) r.period = vm["period"].as<double>();
  if (given(vm, "harmonics")) r.harmonics = vm["harmonics"].as<int>();
  if (given(vm, "starts")) r.starts = vm["starts"].as<int>();
  if (given(vm, "evaluations")) r.evaluations = vm["evaluations"].as<int>();
  if (given(vm, "grid-rate")) r.grid_rate = vm["grid-rate"].as<double>();
  if (given(vm, "check-rate")) r.check_rate = vm["check-rate"].as<double>();
  if (const double s = vm["budget-seconds"].as<double>(); s > 0.0) r.max_seconds = s;
  r.max_sway = vm["max-sway"].as<double>();
  r.max_turn = vm["max-turn"].as<double>();
  r.joint_margin = vm["joint-margin"].as<double>();
  r.max_swing = vm["max-swing"].as<double>();
  r.friction_cone = vm["friction-cone"].as<double>();
  if (vm.count("sole")) r.sole = soleOption(vm);
  r.structural = structuralOptions(vm);
  r.seed = vm["seed"].as<std::uint64_t>();
  try {
    r.check();
  } catch (const InputError& e) {
    throw UsageError(cliText(e.what()));
  }
  return r;
}

}  // namespace

int runFloatingExcite(const po::variables_map& vm) {
  refuseOutside(vm, {"out",       "contacts",     "sensors",   "stance",        "max-sway",
                     "max-turn",  "joint-margin", "max-swing", "friction-cone", "sole",
                     "period",    "harmonics",    "starts",    "evaluations",   "budget-seconds",
                     "grid-rate", "check-rate",   "samples",   "seed",          "tolerance"},
                "excite");
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);  // before the work, not after it
  const FloatingModel model = loadFloating(vm);
  StandingDesignRequest request = standingRequest(vm, model);
  const InterruptGuard guard;
  request.control.stop = guard.flag();
  if (stderrIsTerminal())
    request.control.progress = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
    };
  StandingDesign design;
  try {
    design = designStandingSway(model, request);
  } catch (const Error&) {
    if (!guard.interrupted()) throw;
    std::cerr << "dynid excite: interrupted (Ctrl-C) before any sway met the bounds: nothing "
                 "written\n";
    return kExitInterrupted;
  }
  design.baseline_problem = cliText(design.baseline_problem);
  const StandingDesignSource source{vm["robot"].as<std::string>(), nameListOption(vm, "contacts")};
  writeReportFiles(
      dir, {{"standing_excitation.json",
             jsonText(withProvenance(standingDesignJson(request, design, source)), 2) + "\n"},
            {"standing_excitation.md", standingDesignMarkdown(request, design, source)}});
  std::cout << "dynid excite --floating-base: " << standingDesignSummary(request, design, dir)
            << "  simulate along it: dynid simulate --robot " << shellWord(source.robot)
            << " --floating-base --trajectory " << shellWord(dir + "/standing_excitation.json")
            << " --out DATA.csv\n";
  return exitAfter(guard, "excite", "wrote the best sway so far to " + dir);
}

}  // namespace dynid::cli
