// dynid model show|check|export
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/mjcf.hpp"
#include "data/model_json.hpp"
#include "data/urdf.hpp"

namespace dynid::cli {

namespace {

void show(const Model& model) {
  std::printf("robot %s: %d joints, gravity (%g, %g, %g) m/s^2, drives %s\n", model.name.c_str(),
              model.numJoints(), model.gravity.x(), model.gravity.y(), model.gravity.z(),
              model.drives_enabled ? (model.offsets_enabled ? "on (with offsets)" : "on") : "off");
  std::printf("\n%-4s %-16s %-16s %-11s %-12s %s\n", "#", "link", "joint", "type", "parent",
              "limits [rad or m]");
  for (int i = 0; i < model.numJoints(); ++i) {
    const int p = model.parents[i];
    std::printf("%-4d %-16s %-16s %-11s %-12s [%g, %g]\n", i + 1, model.link_names[i].c_str(),
                model.joint_names[i].c_str(), jointTypeName(model.joint_types[i]),
                p < 0 ? "(base)" : model.link_names[p].c_str(), model.limits[i].lower,
                model.limits[i].upper);
  }
  const ParameterLayout layout = model.parameterLayout();
  const std::vector<std::string> names = standardParameterNames(layout);
  const Eigen::VectorXd theta = model.standardParameters();
  std::printf("\nstandard parameters (link frame origin; SI units):\n");
  for (int i = 0; i < model.numJoints(); ++i) {
    for (int k = 0; k < layout.perLink(); ++k) {
      const int index = i * layout.perLink() + k;
      std::printf("  %-7s % .6g%s", names[index].c_str(), theta(index),
                  (k + 1) % 5 == 0 || k + 1 == layout.perLink() ? "\n" : "");
    }
  }
  std::printf("\npaper parameters (m, centre of mass, principal inertia about it):\n");
  for (int i = 0; i < model.numJoints(); ++i) {
    double dropped = 0.0;
    const auto paper = standardToPaper(toStandardVector(model.inertias[i]), &dropped);
    std::printf("  link %-3d m %-9.6g c (%.6g, %.6g, %.6g)  I (%.6g, %.6g, %.6g)%s\n", i + 1,
                paper(0), paper(1), paper(2), paper(3), paper(4), paper(5), paper(6),
                dropped > 1e-12 ? "  [has products of inertia]" : "");
  }
}

int check(const Model& model, bool json) {
  std::vector<ConsistencyViolation> all;
  for (int i = 0; i < model.numJoints(); ++i) {
    auto v = checkPhysicalConsistency(model.inertias[i], i, model.link_names[i]);
    all.insert(all.end(), v.begin(), v.end());
  }
  if (json) {
    nlohmann::json violations = nlohmann::json::array();
    for (const auto& v : all)
      violations.push_back({{"link", v.link + 1},
                            {"link_name", v.link_name},
                            {"condition", v.condition},
                            {"detail", v.detail}});
    std::cout << nlohmann::json{{"schema_version", 1},
                                {"robot", model.name},
                                {"consistent", all.empty()},
                                {"violations", violations}}
                     .dump(2)
              << "\n";
  } else if (all.empty()) {
    std::printf("%s: all %d links are physically consistent\n", model.name.c_str(),
                model.numJoints());
  } else {
    for (const auto& v : all)
      std::printf("%s: link %d (%s) violates %s: %s\n", model.name.c_str(), v.link + 1,
                  v.link_name.c_str(), v.condition.c_str(), v.detail.c_str());
  }
  return all.empty() ? kExitOk : kExitError;
}

}  // namespace

int runModel(const std::vector<std::string>& args) {
  const std::string usage =
      "dynid model show|check|export --robot R [--drives] [--json] "
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
  if (sub == "check") options.add_options()("json", po::bool_switch(), "print JSON");
  if (sub == "export")
    options.add_options()("format", po::value<std::string>()->required(),
                          "urdf, json or mjcf (MuJoCo)")(
        "out", po::value<std::string>()->required(), "output file, or - for standard output");
  po::variables_map vm;
  if (!parseCommandLine({args.begin() + 1, args.end()}, options, "dynid model " + sub + " ...", vm))
    return kExitOk;
  std::string format;
  if (sub == "export") {
    format = vm["format"].as<std::string>();
    if (format != "urdf" && format != "json" && format != "mjcf")
      throw UsageError("--format must be urdf, json or mjcf, not '" + format + "'");
  }
  const Model model = loadRobotFromOptions(vm);
  if (sub == "show") {
    show(model);
    return kExitOk;
  }
  if (sub == "check") return check(model, vm["json"].as<bool>());
  const std::string text = format == "urdf"   ? modelToUrdf(model)
                           : format == "mjcf" ? modelToMjcf(model)
                                              : modelToJson(model);
  const std::string out = vm["out"].as<std::string>();
  if (out == "-") {
    std::cout << text;
  } else {
    writeFileAtomically(out, text);
    std::cerr << "wrote " << out << "\n";
  }
  return kExitOk;
}

}  // namespace dynid::cli
