// dynid upgrade: a document of an earlier schema version rewritten in the current one
// (analysis/records/upgrade.hpp); an estimate's embedded robot is checked against its recorded
// kinematics and the result read back before it is written.
#include <filesystem>
#include <iostream>

#include "analysis/records/estimate_record.hpp"
#include "analysis/records/upgrade.hpp"
#include "analysis/runs/arm.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/json_number.hpp"
#include "data/model_json.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// An upgraded estimate must be one its readers take, for the robot it recorded.
void checkUpgradedEstimate(const UpgradeOutcome& upgraded, const std::string& file) {
  const nlohmann::json& d = upgraded.document;
  estimateRecordFrom(d, file);  // throws ParseError naming the field
  if (d.contains("kinematics") && d.contains("model")) {
    const std::string difference =
        kinematicsDifference(d["kinematics"], modelFromJson(d["model"].dump(), file));
    if (!difference.empty())
      throw InputError(file +
                       ": the robot given is not the one the estimate was made for: " + difference);
  }
}

}  // namespace

int runUpgrade(const std::vector<std::string>& args) {
  po::options_description options("dynid upgrade");
  options.add_options()(
      "file", po::value<std::string>()->required(),
      "a dynid document of an earlier version (any kind that has had more than one)")(
      "robot", po::value<std::string>(),
      "an estimate's robot, where its robot_spec is not found (same kinematics, checked)")(
      "out", po::value<std::string>()->required(),
      "the document in the current version (a new file, or - for standard output)");
  po::positional_options_description positional;
  positional.add("file", 1);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid upgrade FILE [--robot R] --out NEW", vm, &positional))
    return kExitOk;
  UpgradeRequest request;
  request.file = vm["file"].as<std::string>();
  if (vm.count("robot")) request.robot_spec = vm["robot"].as<std::string>();
  const std::string out = vm["out"].as<std::string>();
  std::error_code error;
  if (out != "-" && std::filesystem::equivalent(out, request.file, error))
    throw UsageError(
        "--out is the document itself: give a new file (the original stays as it "
        "is until you replace it)");
  const UpgradeOutcome upgraded = upgradeDocument(request);
  if (upgraded.kind == std::string(kEstimateDocument.kind))
    checkUpgradedEstimate(upgraded, request.file);
  printWarnings(upgraded.notes, "note: ");
  if (writeOutput(out, jsonText(upgraded.document, 2) + "\n"))
    std::cerr << (upgraded.from == upgraded.to
                      ? request.file + " is already " + upgraded.kind + " version " +
                            std::to_string(upgraded.to) + "; wrote it to " + out
                      : request.file + ": " + upgraded.kind + " version " +
                            std::to_string(upgraded.from) + " -> " + std::to_string(upgraded.to) +
                            "; wrote " + out)
              << "\n";
  return kExitOk;
}

}  // namespace dynid::cli
