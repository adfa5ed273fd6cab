// dynid payload: what was added at a link of an identified arm, with the arm held fixed.
#include <iostream>

#include "analysis/payload/payload.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/payload_record.hpp"
#include "analysis/runs/arm.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "reports/output.hpp"
#include "reports/payload_report.hpp"

namespace dynid::cli {

namespace {
Eigen::Vector3d threeNumbers(const po::variables_map& vm, const char* option) {
  const std::vector<double> v = fixedList(vm, option, 3, "three numbers: x,y,z");
  return {v[0], v[1], v[2]};
}

void addPayloadOptions(po::options_description& options) {
  std::string formats;
  for (const std::string& f : payloadFormats()) formats += (formats.empty() ? "" : ", ") + f;
  options.add_options()(
      "arm", po::value<std::string>()->required(),
      "the identified arm: identify's estimate.json, an identified URDF or a dynid .json model")(
      "robot", po::value<std::string>(), "for an estimate: the robot (default: the one it names)")(
      "drive-terms", po::value<std::string>(),
      "for a URDF or model arm: its drive terms, e.g. fv,fc (default: none)")(
      "data", po::value<std::string>()->required(),
      "prepared dataset CSV with the payload attached")(
      "unloaded", po::value<std::string>(),
      "the same commanded motion without the payload: the torque difference is used")(
      "prior", po::value<std::string>(),
      "a prior payload: a payload.json or payload.body.json (default: uninformative)")(
      "refit-friction", po::bool_switch(),
      "re-estimate the arm's friction terms with the payload (load-dependent friction)")(
      "payload-mass", po::value<double>(),
      "drive gains: the payload's known mass [kg] (needs --unloaded)")(
      "payload-com", po::value<std::string>(),
      "drive gains: its known centre of mass in the attachment frame, x,y,z [m]")(
      "max-motion-difference",
      po::value<double>()->default_value(PayloadRequest{}.max_motion_difference))(
      "format", po::value<std::vector<std::string>>()->composing(),
      ("also write the payload in a controller's convention (repeat or comma-separate): " + formats)
          .c_str())(
      "write-urdf", po::value<std::string>(),
      "a copy of the arm's URDF with the payload as a fixed link (the arm from a URDF, or an "
      "estimate of a URDF robot); - for standard output")(
      "out", po::value<std::string>()->required(),
      "output directory (payload.json, report.md, report.html)");
}

/// --write-urdf: the file to write (empty: none), and the URDF it comes from in the request.
std::string writeUrdfOption(const po::variables_map& vm, const LoadedArm& arm,
                            PayloadRequest& request) {
  if (!vm.count("write-urdf")) return "";
  if (!isUrdfSpec(arm.robot_spec))
    throw UsageError("--write-urdf needs an arm that is a URDF robot, not '" + arm.robot_spec +
                     "'");
  const std::string urdf_path = vm["write-urdf"].as<std::string>();
  if (isInputFile(urdf_path))
    throw UsageError("--write-urdf: '" + urdf_path +
                     "' is an input of this command; name another file (the input stays)");
  request.urdf_file = arm.robot_spec;
  request.urdf_carries_arm = arm.from_estimate;
  return urdf_path;
}
}  // namespace

int runPayload(const std::vector<std::string>& args) {
  po::options_description options("dynid payload");
  addPayloadOptions(options);
  addAttachmentOptions(options, "the payload");
  addPriorWeightOption(options);
  po::variables_map vm;
  const std::string usage =
      "dynid payload --arm estimate.json --data loaded.csv [--unloaded unloaded.csv] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);
  refuseUnused(vm, vm.count("payload-mass") > 0, {"payload-com"}, "applies with --payload-mass");
  refuseUnused(vm, vm.count("unloaded") > 0, {"payload-mass"},
               "needs --unloaded: drive gains come from a loaded and an unloaded run");

  PayloadRequest request;
  std::vector<std::string> chosen;
  if (vm.count("format")) try {
      chosen = payloadFormatList(vm["format"].as<std::vector<std::string>>());
    } catch (const InputError& e) {
      throw UsageError(std::string("--format: ") + e.what());
    }
  std::optional<DriveTerms> terms;
  if (vm.count("drive-terms"))
    terms = parseOption(vm, "drive-terms", [](const std::string& t) { return parseDriveTerms(t); });
  std::vector<std::string> warnings;
  const LoadedArm arm =
      loadArm(vm["arm"].as<std::string>(), vm.count("robot") ? vm["robot"].as<std::string>() : "",
              terms, &warnings);
  printWarnings(warnings);
  request.arm = arm.model;
  request.arm_source = vm["arm"].as<std::string>();
  request.arm_model = arm.source;
  request.data_file = vm["data"].as<std::string>();
  if (vm.count("unloaded")) request.unloaded_file = vm["unloaded"].as<std::string>();
  if (vm.count("link")) request.link = vm["link"].as<std::string>();
  request.tool = attachmentFrameOption(vm);
  if (vm.count("prior")) {
    const std::string file = vm["prior"].as<std::string>();
    request.prior = payloadBodyFrom(parseJson(readFile(file), file), file);
  }
  request.prior_weight = priorWeightOption(vm);
  request.refit_friction = vm["refit-friction"].as<bool>();
  if (vm.count("payload-mass")) request.known_mass = vm["payload-mass"].as<double>();
  if (vm.count("payload-com")) request.known_com = threeNumbers(vm, "payload-com");
  request.max_motion_difference = vm["max-motion-difference"].as<double>();
  const std::string urdf_path = writeUrdfOption(vm, arm, request);
  PayloadOutcome outcome = payloadRun(request);
  cliTexts(outcome.warnings);  // the fields they name, as this command's flags
  cliTexts(outcome.advice);
  // The summary goes to standard error when standard output carries the URDF.
  (urdf_path == "-" ? std::cerr : std::cout) << writePayload(dir, outcome, chosen, urdf_path);
  return kExitOk;
}

}  // namespace dynid::cli
