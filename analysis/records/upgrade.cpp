#include "analysis/records/upgrade.hpp"

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"

namespace dynid {

namespace {

using json = nlohmann::json;

/// The kinds with earlier versions, and how a document of each is told when it has no "kind"
/// (estimate.json and search.json 1 did not write one).
const DocumentType* kindOf(const json& d, const std::string& file) {
  static const DocumentType* const kUpgradable[] = {&kEstimateDocument, &kExcitationDocument,
                                                    &kMonitorThresholdsDocument, &kSearchDocument};
  if (d.contains("kind")) {
    for (const DocumentType* t : kUpgradable)
      if (d["kind"] == t->kind) return t;
    throw ParseError(file, 0, "kind",
                     (d["kind"].is_string() ? "'" + d["kind"].get<std::string>() + "'"
                                            : std::string("this kind")) +
                         " has no earlier version to upgrade: only estimate, excitation, monitor "
                         "thresholds and search documents do");
  }
  if (d.contains("standard_estimate") && d.contains("base_parameters")) return &kEstimateDocument;
  if (d.contains("settings") && d.contains("history") && d.contains("estimate"))
    return &kSearchDocument;
  throw ParseError(file, 0, "kind",
                   "missing, and the keys are not those of an estimate or a search: not a dynid "
                   "document that has earlier versions");
}

/// The note for a document from before `version` recorded its provenance.
std::string noProvenanceNote(int version) {
  return "versions before " + std::to_string(version) +
         " recorded no provenance (which dynid, command and inputs made it): none is added";
}

/// estimate.json 1-5 -> 6: the robot embedded (loaded from robot_spec beside the document, or
/// `robot_spec`); rest velocities, the covariance policy and the fit's rows stay as recorded.
void upgradeEstimate(json& d, int from, const UpgradeRequest& request,
                     std::vector<std::string>& notes) {
  d["kind"] = kEstimateDocument.kind;
  if (!d.contains("model")) {
    if (request.robot_spec.empty() && !d.contains("robot_spec"))
      throw ParseError(request.file, 0, "robot_spec",
                       "missing: the estimate does not say which robot it is for; give `robot`");
    const std::string spec =
        request.robot_spec.empty() ? d["robot_spec"].get<std::string>() : request.robot_spec;
    const std::string where =
        request.robot_spec.empty() ? specBesideDocument(spec, request.file) : spec;
    std::string terms;
    if (d.contains("drive_terms"))
      for (const json& t : d["drive_terms"])
        terms += (terms.empty() ? "" : ",") + t.get<std::string>();
    RobotOptions options;
    options.drive_terms = parseDriveTerms(terms.empty() ? "none" : terms);
    Model robot;
    try {
      robot = loadRobot(where, options);
    } catch (const Error& e) {
      throw InputError(request.file + ": cannot load the robot it was made for ('" + spec +
                       "'; give it with `robot`): " + e.what());
    }
    ModelSource source = modelSourceOf(where);
    source.spec = spec;
    d["model"] = json::parse(modelToJson(robot));
    d["model_source"] = modelSourceJson(source);
    notes.push_back("embedded the robot it was made for, loaded from " + where +
                    (source.sha256.empty() ? "" : " (SHA-256 " + source.sha256 + ")"));
  }
  if (from < 2)
    notes.push_back(
        "version 1 recorded no rest velocities: none are added (read as 0 rad/s, as "
        "before)");
  if (from < 3)
    notes.push_back(
        "versions 1 and 2 recorded no covariance policy: the covariance stays the "
        "white one it was");
  if (from < 4) notes.push_back("versions 1 to 3 recorded no fit_rows: none are added");
  if (from < 6) notes.push_back(noProvenanceNote(6));
}

/// excitation.json 1-3 -> 4: `model` was the robot's name; version 3's is the robot itself, which
/// an older design does not say enough to load (its drive terms): left out.
void upgradeExcitation(json& d, int from, std::vector<std::string>& notes) {
  if (d.contains("model") && d["model"].is_string()) {
    notes.push_back("`model` named the robot ('" + d["model"].get<std::string>() +
                    "'); version 3's embeds it, which this design does not record enough to "
                    "do (its drive terms): left out (run excite again to embed it)");
    d.erase("model");
  }
  if (from < 2) {
    d["payload_link"] = nullptr;
    notes.push_back("payload_link null: version 1 designs were for the whole arm");
  }
  if (from < 4) notes.push_back(noProvenanceNote(4));
}

/// thresholds.json 1-4 -> 5: the arm states and regimes absent before stay null; the arm is not
/// embedded (the thresholds name the robot, not its file).
void upgradeThresholds(json& d, int from, std::vector<std::string>& notes) {
  if (from < 2) {
    d["rest_velocity"] = nullptr;
    d["thresholds_at_rest"] = nullptr;
    notes.push_back(
        "version 1 had no thresholds at rest: null (the moving thresholds apply at "
        "rest, as before)");
  }
  if (from < 3) {
    d["moving_regimes"] = nullptr;
    notes.push_back("no moving regimes before version 3: null (the single moving threshold)");
  }
  if (from < 4)
    notes.push_back("the arm is not embedded: the thresholds name the robot, not its file");
  if (from < 5) notes.push_back(noProvenanceNote(5));
}

}  // namespace

UpgradeOutcome upgradeDocument(const UpgradeRequest& request) {
  UpgradeOutcome out;
  out.document = parseJson(readFile(request.file), request.file);
  json& d = out.document;
  if (!d.is_object()) throw ParseError(request.file, 0, "", "expected a JSON object");
  const DocumentType& type = *kindOf(d, request.file);
  out.kind = type.kind;
  out.to = type.schema_version;
  if (!d.contains("schema_version") || !d["schema_version"].is_number_integer() ||
      d["schema_version"] < 1)
    throw ParseError(request.file, 0, "schema_version", "expected an integer >= 1");
  if (d["schema_version"] > type.schema_version)
    throw InputError(request.file + ": " + type.kind + " version " + d["schema_version"].dump() +
                     " is later than this dynid's (" + std::to_string(type.schema_version) +
                     "): written by a newer dynid");
  out.from = d["schema_version"].get<int>();
  if (out.from == out.to) return out;
  if (&type == &kEstimateDocument) upgradeEstimate(d, out.from, request, out.notes);
  if (&type == &kExcitationDocument) upgradeExcitation(d, out.from, out.notes);
  if (&type == &kMonitorThresholdsDocument) upgradeThresholds(d, out.from, out.notes);
  if (&type == &kSearchDocument) {
    d["kind"] = kSearchDocument.kind;
    if (out.from < 2)
      out.notes.push_back(
          "the robot searched on is not embedded: version 1 names it, not its file");
    out.notes.push_back(noProvenanceNote(3));
  }
  d["schema_version"] = out.to;
  return out;
}

std::string olderVersionNote(const std::string& file, const std::string& kind, int version,
                             int current) {
  return file + " is " + kind + " version " + std::to_string(version) + " (current " +
         std::to_string(current) + "): read as it is; upgrading the document rewrites it in " +
         "version " + std::to_string(current);
}

}  // namespace dynid
