// dynid fleet: many robots of one model at once. Each robot's logs (or summaries) lie in a folder
// of its own, named after the robot; the fleet's prior, the robots outside it and each robot's
// estimate with the prior (analysis/fleet/fleet.hpp).
#include <filesystem>
#include <iostream>
#include <map>

#include "analysis/fleet/fleet.hpp"
#include "analysis/records/fleet_manifest.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "reports/fleet_report.hpp"

namespace dynid::cli {

namespace {

/// The robots of `files` (logs or summaries), one per folder in the order first given, named
/// after the folder (its whole path when two folders share a name). UsageError for a file
/// without a folder of its own.
std::vector<FleetRobotInput> robotsByFolder(const std::vector<std::string>& files, bool summaries,
                                            const char* option) {
  std::vector<std::string> folders;
  std::map<std::string, std::vector<std::string>> by_folder;
  for (const std::string& file : files) {
    const std::string folder =
        std::filesystem::path(file).parent_path().lexically_normal().string();
    if (folder.empty() || folder == ".")
      throw UsageError(std::string("--") + option + " " + file +
                       ": each robot's files go in a folder of its own, named after the robot "
                       "(robot_a/run1.csv)");
    if (by_folder.find(folder) == by_folder.end()) folders.push_back(folder);
    by_folder[folder].push_back(file);
  }
  std::map<std::string, int> short_names;
  for (const std::string& f : folders) ++short_names[std::filesystem::path(f).filename().string()];
  std::vector<FleetRobotInput> out;
  for (const std::string& f : folders) {
    FleetRobotInput robot;
    const std::string name = std::filesystem::path(f).filename().string();
    robot.name = short_names[name] > 1 ? f : name;
    (summaries ? robot.summary_files : robot.data_files) = by_folder[f];
    out.push_back(std::move(robot));
  }
  return out;
}

/// The robots the options name: --data or --summaries grouped by folder, or a --manifest's.
/// UsageError unless exactly one of the three is given, or for --rest-velocity or
/// --torque-filter with summaries.
std::vector<FleetRobotInput> robotsOf(const po::variables_map& vm) {
  if ((given(vm, "data") ? 1 : 0) + (given(vm, "summaries") ? 1 : 0) +
          (given(vm, "manifest") ? 1 : 0) !=
      1)
    throw UsageError(
        "give the robots' logs (--data), their summaries (--summaries) or a manifest "
        "(--manifest), one of them");
  const bool summaries = given(vm, "summaries");
  std::vector<FleetRobotInput> robots;
  refuseUnused(vm, !summaries, {"rest-velocity", "torque-filter"},
               "applies to --data: a summary holds its logs' rest velocities and torque filter");
  if (given(vm, "manifest")) {
    for (FleetManifestRobot& r : readFleetManifest(vm["manifest"].as<std::string>())) {
      refuseUnused(vm, r.summaries.empty(), {"rest-velocity", "torque-filter"},
                   "applies to logs: the manifest's robot " + r.name +
                       " is given by summaries, which hold their logs' rest velocities and "
                       "torque filter");
      robots.push_back({r.name, std::move(r.data), std::move(r.summaries), nullptr});
    }
  } else {
    robots = robotsByFolder(vm[summaries ? "summaries" : "data"].as<std::vector<std::string>>(),
                            summaries, summaries ? "summaries" : "data");
  }
  return robots;
}

}  // namespace

int runFleet(const std::vector<std::string>& args) {
  po::options_description options("dynid fleet");
  addRobotOptions(options, true);
  addStructuralOptions(options);
  options.add_options()(
      "data", po::value<std::vector<std::string>>()->multitoken(),
      "the robots' logs (dataset CSVs), each robot's in a folder named after it: robot_a/*.csv "
      "robot_b/*.csv ...")(
      "summaries", po::value<std::vector<std::string>>()->multitoken(),
      "or their summaries (dynid summarize), each robot's in a folder named after it")(
      "manifest", po::value<std::string>(),
      "or a fleet manifest naming each robot and its logs or summaries (docs/FLEET.md)")(
      "method", po::value<std::string>()->default_value("ols"),
      "each robot's estimate: ols or wls")(
      "covariance", po::value<std::string>()->default_value("hac"),
      "each robot's covariance: hac (the white one widened by the robust covariance's median "
      "inflation: correlated residuals count) or white")(
      "flag-level", po::value<double>()->default_value(0.01),
      "the chance that a fleet of robots alike has one robot flagged, in (0, 0.5]")(
      "out", po::value<std::string>()->required(),
      "output directory (fleet.json, report.md, report.html)");
  addTorqueFilterOption(options,
                        "the low-pass each log's torque went through (default: the prepare.json "
                        "beside it says)");
  addRestVelocityOption(options);
  addThreadsOption(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid fleet --robot R [--drive-terms T] --data robot_a/*.csv "
                        "robot_b/*.csv ... --out DIR\n       dynid fleet --robot R --summaries "
                        "robot_a/*.summary.json ... --out DIR\n       dynid fleet --robot R "
                        "--manifest fleet.json --out DIR",
                        vm))
    return kExitOk;
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);
  FleetRequest request;
  request.model = loadRobotFromOptions(vm);
  request.robot_spec = vm["robot"].as<std::string>();
  request.structural = structuralOptions(vm);
  request.robots = robotsOf(vm);
  request.method = parseOption(vm, "method", [](const std::string& name) {
    const Method m = parseMethod(name);
    if (m != Method::kOls && m != Method::kWls)
      throw UsageError("--method " + name + ": a fleet takes ols or wls");
    return m;
  });
  request.covariance = parseOption(vm, "covariance", covariancePolicyFrom);
  request.prior.flag_level = vm["flag-level"].as<double>();
  request.rest_velocity = restVelocityOption(vm, request.model.numJoints());
  request.torque_filter = torqueFilterOption(vm);
  request.threads = threadsOption(vm);
  if (stderrIsTerminal())
    request.control.progress = [](const std::string& line) {
      std::cerr << "[fleet] " << line << "\n";
    };
  InterruptGuard guard;
  request.control.stop = guard.flag();
  const FleetOutcome outcome = fleetRun(request);
  if (!outcome.robots.empty()) std::cout << writeFleet(dir, outcome);
  return exitAfter(guard, "fleet",
                   outcome.robots.empty()
                       ? "nothing is written: fewer than three robots were estimated"
                       : "the fleet of the " + std::to_string(outcome.robots.size()) +
                             " robots estimated whole is written");
}

}  // namespace dynid::cli
