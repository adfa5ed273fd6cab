// dynid model show|check|export|attach
#include <iostream>

#include "analysis/payload/attach.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/payload_record.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/mjcf.hpp"
#include "data/robots.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// dynid model attach: the robot with a known body added to a link, written as a model file.
int runAttach(const std::vector<std::string>& args) {
  po::options_description options("dynid model attach");
  addRobotOptions(options);
  addAttachmentOptions(options, "the body");
  options.add_options()("mass", po::value<double>(), "the body's mass [kg]")(
      "com", po::value<std::string>(), "its centre of mass in its frame, x,y,z [m] (default 0)")(
      "inertia", po::value<std::string>(),
      "its inertia about the centre of mass in its frame's axes, Ixx,Ixy,Ixz,Iyy,Iyz,Izz "
      "[kg m^2] (default 0: a point mass)")(
      "body", po::value<std::string>(),
      "instead of --mass, --com and --inertia: a payload.json or payload.body.json (dynid "
      "payload's estimate, in its attachment frame)")(
      "format", po::value<std::string>()->default_value("json"), "urdf, json or mjcf (MuJoCo)")(
      "out", po::value<std::string>()->required(), "output file, or - for standard output");
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid model attach --robot R --mass M [--com x,y,z] [--inertia "
                        "Ixx,Ixy,Ixz,Iyy,Iyz,Izz] [--link L] [--tool-xyz ...] --out FILE",
                        vm))
    return kExitOk;
  const std::string format = vm["format"].as<std::string>();
  if (format != "urdf" && format != "json" && format != "mjcf")
    throw UsageError("--format must be urdf, json or mjcf, not '" + format + "'");
  const bool given = vm.count("mass") || vm.count("com") || vm.count("inertia");
  if (given == (vm.count("body") > 0))
    throw UsageError("give the body as --mass (with --com, --inertia) or as --body, one of them");
  const Model arm = loadRobotFromOptions(vm);
  const Pose<double> frame = attachmentFrameOption(vm);
  Vector10d body;
  if (vm.count("body")) {
    const std::string file = vm["body"].as<std::string>();
    body = payloadBodyFrom(parseJson(readFile(file), file), file);
  } else {
    if (!vm.count("mass")) throw UsageError("--com and --inertia need --mass");
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    if (vm.count("com")) {
      const std::vector<double> v = fixedList(vm, "com", 3, "three numbers: x,y,z");
      com = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    if (vm.count("inertia")) {
      const std::vector<double> v =
          fixedList(vm, "inertia", 6, "six numbers: Ixx,Ixy,Ixz,Iyy,Iyz,Izz");
      inertia << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
    }
    body = bodyFromCentre(vm["mass"].as<double>(), com, inertia);
  }
  const int link = linkIndex(arm, vm.count("link") ? vm["link"].as<std::string>() : "");
  const Model loaded = attachBody(arm, link, frame, body);
  const std::string out = vm["out"].as<std::string>();
  printWarnings(modelExportNotes(loaded, format), "note: ");
  if (writeOutput(out, modelDocument(loaded, format)))
    std::cerr << "wrote " << out << ": " << arm.name << " with a " << formatNumber(body[0], 4)
              << " kg body on link " << arm.link_names[static_cast<std::size_t>(link)] << "\n";
  return kExitOk;
}

}  // namespace

int runModel(const std::vector<std::string>& args) {
  const std::string usage =
      "dynid model show|check|export|attach --robot R [--drives] [--fix-joints J1,J2] [--json] "
      "[--format urdf|json|mjcf --out FILE]";
  if (args.empty() ||
      (args[0] != "show" && args[0] != "check" && args[0] != "export" && args[0] != "attach")) {
    if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
      std::cout << "usage: " << usage
                << "\n\n  show    kinematics, limits and parameters (standard and paper form)\n"
                   "  check   physical consistency of every link (exit 1 when a link violates "
                   "it)\n  export  write the model as URDF or JSON\n"
                   "  attach  the model with a known body fixed to a link (a tool, a payload "
                   "estimate), written as URDF, JSON or MJCF\n";
      return kExitOk;
    }
    throw UsageError("expected a subcommand: show, check, export or attach\nusage: " + usage);
  }
  if (args[0] == "attach") return runAttach({args.begin() + 1, args.end()});
  const std::string sub = args[0];
  po::options_description options("dynid model " + sub);
  addRobotOptions(options);
  options.add_options()(
      "fix-joints", po::value<std::string>(),
      "a URDF's moving joints to treat as fixed at zero, comma-separated (a gripper's fingers): "
      "their links merge into the parent body; export the result as the arm to identify");
  if (sub == "check") options.add_options()("json", po::bool_switch(), "print JSON");
  if (sub == "export")
    options.add_options()("format", po::value<std::string>()->required(),
                          "urdf, json or mjcf (MuJoCo)")(
        "out", po::value<std::string>()->required(), "output file, or - for standard output");
  po::variables_map vm;
  if (!parseCommandLine({args.begin() + 1, args.end()}, options, "dynid model " + sub + " ...", vm))
    return kExitOk;
  const std::string format = sub == "export" ? vm["format"].as<std::string>() : "";
  if (sub == "export" && format != "urdf" && format != "json" && format != "mjcf")
    throw UsageError("--format must be urdf, json or mjcf, not '" + format + "'");
  std::vector<std::string> fixed;
  if (vm.count("fix-joints")) {
    if (!isUrdfSpec(vm["robot"].as<std::string>()))
      throw UsageError("--fix-joints applies to a URDF robot, not '" +
                       vm["robot"].as<std::string>() + "'");
    const std::string list = vm["fix-joints"].as<std::string>();
    for (std::size_t start = 0; start <= list.size();) {
      const std::size_t comma = std::min(list.find(',', start), list.size());
      if (comma == start) throw UsageError("--fix-joints: an empty joint name in '" + list + "'");
      fixed.push_back(list.substr(start, comma - start));
      start = comma + 1;
    }
  }
  const Model model = loadRobotFromOptions(vm, fixed);
  if (sub == "show") {
    std::cout << modelShowText(model);
    return kExitOk;
  }
  if (sub == "check") {
    const std::vector<ConsistencyViolation> violations = consistencyViolations(model);
    if (vm["json"].as<bool>())
      std::cout << jsonText(modelCheckJson(model, violations), 2) << "\n";
    else
      std::cout << modelCheckText(model, violations);
    return violations.empty() ? kExitOk : kExitError;
  }
  const std::string out = vm["out"].as<std::string>();
  printWarnings(modelExportNotes(model, format), "note: ");  // what URDF or MJCF drops
  if (writeOutput(out, modelDocument(model, format))) std::cerr << "wrote " << out << "\n";
  return kExitOk;
}

}  // namespace dynid::cli
