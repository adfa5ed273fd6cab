// dynid model show|check|export
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/json_number.hpp"
#include "data/robots.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

int runModel(const std::vector<std::string>& args) {
  const std::string usage =
      "dynid model show|check|export --robot R [--drives] [--fix-joints J1,J2] [--json] "
      "[--format urdf|json|mjcf --out FILE]";
  if (args.empty() || (args[0] != "show" && args[0] != "check" && args[0] != "export")) {
    if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
      std::cout << "usage: " << usage
                << "\n\n  show    kinematics, limits and parameters (standard and paper form)\n"
                   "  check   physical consistency of every link (exit 1 when a link violates "
                   "it)\n  export  write the model as URDF or JSON\n";
      return kExitOk;
    }
    throw UsageError("expected a subcommand: show, check or export\nusage: " + usage);
  }
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
  if (writeOutput(out, modelDocument(model, format))) std::cerr << "wrote " << out << "\n";
  return kExitOk;
}

}  // namespace dynid::cli
