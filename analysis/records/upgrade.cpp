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
  static const DocumentType* const kUpgradable[] = {&kEstimateDocument,
                                                    &kExcitationDocument,
                                                    &kMonitorThresholdsDocument,
                                                    &kSearchDocument,
                                                    &kRefineDocument,
                                                    &kPredictionDocument,
                                                    &kPayloadDocument,
                                                    &kPayloadBodyDocument,
                                                    &kMonitorDocument,
                                                    &kAuditDocument,
                                                    &kStudyDocument,
                                                    &kPrepareDocument,
                                                    &kIdentifiabilityDocument,
                                                    &kDemoDocument,
                                                    &kFloatingPrepareDocument,
                                                    &kFloatingIdentificationDocument};
  if (d.contains("kind")) {
    for (const DocumentType* t : kUpgradable)
      if (d["kind"] == t->kind) return t;
    throw ParseError(file, 0, "kind",
                     (d["kind"].is_string() ? "'" + d["kind"].get<std::string>() + "'"
                                            : std::string("this kind")) +
                         " has no earlier version to upgrade: it has had one version only");
  }
  if (d.contains("standard_estimate") && d.contains("base_parameters")) return &kEstimateDocument;
  if (d.contains("settings") && d.contains("history") && d.contains("estimate"))
    return &kSearchDocument;
  throw ParseError(file, 0, "kind",
                   "missing, and the keys are not those of an estimate or a search: not a dynid "
                   "document that has earlier versions");
}

/// Renames keys of the object at `at` (a top-level key; "" the document itself) where present,
/// with a note each: the names a version changed.
void renameKeys(json& d, const std::string& at,
                const std::vector<std::pair<std::string, std::string>>& names,
                std::vector<std::string>& notes) {
  json* object = at.empty() ? &d : (d.contains(at) ? &d[at] : nullptr);
  if (object == nullptr || !object->is_object()) return;
  for (const auto& [old_name, new_name] : names) {
    if (!object->contains(old_name) || object->contains(new_name)) continue;
    (*object)[new_name] = (*object)[old_name];
    object->erase(old_name);
    notes.push_back((at.empty() ? "" : at + ".") + old_name + " is named " + new_name + " now");
  }
}

/// What a version of a kind added that an older document did not record: absent after the upgrade
/// (its readers, where it has any, take it as they always did), and said.
struct Added {
  const DocumentType* type;
  int version;
  const char* what;
};
constexpr const char* kProvenance = "provenance (which dynid, command and inputs made it)";
constexpr const char* kModel = "model and model_source (the robot, embedded)";
const Added kAdded[] = {
    {&kEstimateDocument, 6, kProvenance},
    // estimate.json 7's data.sources: absent in an earlier version, which came from a dataset.
    // estimate.json 8's front: absent in an earlier version, which had no identify front
    // (`front_weights`).
    {&kExcitationDocument, 4, kProvenance},
    {&kExcitationDocument, 5,
     "stand (the stand orientations chosen for a suspended robot's design; none were then)"},
    {&kMonitorThresholdsDocument, 5, kProvenance},
    {&kSearchDocument, 3, kProvenance},
    {&kRefineDocument, 2, kModel},
    {&kRefineDocument, 3, kProvenance},
    {&kPredictionDocument, 3, "rest_velocity and at_rest (the prediction at rest)"},
    {&kPredictionDocument, 4,
     "torque_filter, torque_filter_source and compared_rows (its errors counted every row)"},
    {&kPredictionDocument, 5, kModel},
    {&kPredictionDocument, 6, kProvenance},
    {&kPayloadDocument, 2,
     "null values for the quantities the log does not determine (here each keeps its number in "
     "value; its half_width_95 says how well it is known)"},
    {&kPayloadDocument, 3, kModel},
    {&kPayloadDocument, 4, kProvenance},
    {&kPayloadBodyDocument, 2, kProvenance},
    {&kMonitorDocument, 2, "each event's contact_link, and calibration_confidence"},
    {&kMonitorDocument, 3, "each event's state (at rest or moving)"},
    {&kMonitorDocument, 4, "each event's regime"},
    {&kMonitorDocument, 5, kModel},
    {&kMonitorDocument, 6, kProvenance},
    {&kAuditDocument, 2, "dispersion, covariance_policies and each parameter's p_scaled"},
    {&kAuditDocument, 3, kModel},
    {&kAuditDocument, 4, kProvenance},
    {&kStudyDocument, 2, kModel},
    {&kStudyDocument, 3, kProvenance},
    {&kStudyDocument, 4, "front and choice (the combined estimator's front, the estimate chosen)"},
    {&kStudyDocument, 5, "each front point's standard parameters and choice.estimate"},
    {&kPrepareDocument, 2, "runs' file and time_offset, stalled repeats and current_to_torque"},
    {&kPrepareDocument, 3, kProvenance},
    {&kIdentifiabilityDocument, 2, kProvenance},
    {&kDemoDocument, 2, kProvenance},
    {&kFloatingPrepareDocument, 2, "contact_threshold and thresholded_contacts"},
    {&kFloatingIdentificationDocument, 2,
     "payload.from and payload.unloaded (a payload from a loaded/unloaded pair)"},
    {&kFloatingIdentificationDocument, 3,
     "gc and each set's gc_error (the GC error of each estimate)"},
    {&kFloatingIdentificationDocument, 4,
     "each set's combined (the combined estimator's run, with that method)"},
};

/// One note per version after `from` whose additions the document lacks.
void noteAdded(const DocumentType& type, int from, std::vector<std::string>& notes) {
  for (const Added& a : kAdded)
    if (a.type == &type && from < a.version)
      notes.push_back("version " + std::to_string(a.version) + " added " + a.what +
                      ": not recorded here, left absent");
}

/// The key changes of the documents that are not read back: prediction.json 2 named its per-joint
/// errors as estimate.json does, prepare.json 2 listed its tables.
void renameWritten(json& d, const DocumentType& type, int from, std::vector<std::string>& notes) {
  if (&type == &kPredictionDocument && from < 2)
    for (const char* at : {"", "raw_measurement"})
      renameKeys(d, at,
                 {{"torque_rms", "residual_rms"}, {"normalised_rms", "joint_relative_error"}},
                 notes);
  if (&type == &kPrepareDocument && from < 2 && d.contains("sources") && d["sources"].is_object() &&
      d["sources"].contains("table")) {
    d["sources"]["tables"] = json::array({d["sources"]["table"]});
    d["sources"].erase("table");
    notes.push_back("sources.table is sources.tables now (a list)");
  }
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
  if (from < 2) {
    renameKeys(d, "validation", {{"torque_rms", "residual_rms"}}, notes);
    notes.push_back(
        "version 1 recorded no rest velocities: none are added (read as 0 rad/s, as "
        "before)");
  }
  if (from < 3)
    notes.push_back(
        "versions 1 and 2 recorded no covariance policy: the covariance stays the "
        "white one it was");
  if (from < 4) notes.push_back("versions 1 to 3 recorded no fit_rows: none are added");
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
  }
  renameWritten(d, type, out.from, out.notes);
  noteAdded(type, out.from, out.notes);
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
