// Documents of earlier versions brought to the current one (analysis/records/upgrade.hpp). The
// version 1 estimate, search and excitation are files dynid wrote then (kept as fuzz seeds since
// 2026-11-24); later versions of the estimate and the thresholds, and the documents no command
// reads back, are made by the changes document.hpp lists, as no binary of those versions is kept.
#include "analysis/records/upgrade.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/records/excitation_record.hpp"
#include "analysis/records/monitor_record.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

std::string seed(const std::string& name) {
  return std::string(DYNID_SOURCE_DIR) + "/tests/fuzz/corpus/" + name;
}

std::string asFile(const std::string& name, const nlohmann::json& document) {
  const std::string path = test::tempPath(name);
  writeFileAtomically(path, document.dump(2));
  return path;
}

// estimate.json 1 (no kind, no rest velocities, no covariance policy, no model) -> 5: the robot
// it names is embedded, and the current reader takes the result with the same parameters.
TEST(Upgrade, AVersion1EstimateGetsItsRobotAndReadsAsCurrent) {
  const std::string file = seed("estimate_json/puma560_ols.json");
  const UpgradeOutcome up = upgradeDocument({file, ""});
  EXPECT_EQ(up.kind, kEstimateDocument.kind);
  EXPECT_EQ(up.from, 1);
  EXPECT_EQ(up.to, kEstimateDocument.schema_version);
  EXPECT_EQ(up.document["schema_version"], kEstimateDocument.schema_version);
  EXPECT_EQ(up.document["kind"], kEstimateDocument.kind);
  EXPECT_EQ(modelFromJson(up.document["model"].dump(), "m").name, "puma560");
  EXPECT_EQ(up.document["model_source"]["spec"], "puma560");
  // The robot embedded; rest, covariance, fit rows and provenance not recorded.
  ASSERT_EQ(up.notes.size(), 5u);
  const EstimateRecord before = estimateRecordFrom(parseJson(readFile(file), file), file);
  const EstimateRecord after = estimateRecordFrom(up.document, "upgraded");
  EXPECT_EQ(before.schema_version, 1);
  EXPECT_EQ(after.schema_version, kEstimateDocument.schema_version);
  EXPECT_EQ(after.standard, before.standard);
  EXPECT_EQ(after.drive_terms, before.drive_terms);
  // Upgrading the current document changes nothing; versions 2 to 4 of it (the same keys, no
  // model) get the same robot back.
  const UpgradeOutcome again = upgradeDocument({asFile("upgraded.json", up.document), ""});
  EXPECT_EQ(again.from, again.to);
  EXPECT_EQ(again.document, up.document);
  for (int version = 2; version < kEstimateDocument.schema_version; ++version) {
    nlohmann::json older = up.document;
    older["schema_version"] = version;
    older.erase("model");
    older.erase("model_source");
    const UpgradeOutcome o = upgradeDocument({asFile("older.json", older), ""});
    EXPECT_EQ(o.from, version);
    EXPECT_EQ(o.document, up.document) << version;
  }
}

// search.json 1 -> 3 and excitation.json 1 -> 5: what they did not record stays absent, said.
TEST(Upgrade, Version1SearchesAndDesignsReadAsCurrent) {
  const UpgradeOutcome search = upgradeDocument({seed("search_json/ga_search.json"), ""});
  EXPECT_EQ(search.from, 1);
  EXPECT_EQ(search.document["schema_version"], kSearchDocument.schema_version);
  EXPECT_EQ(search.document["kind"], kSearchDocument.kind);
  EXPECT_FALSE(search.document.contains("model"));
  EXPECT_EQ(search.notes.size(), 2u);  // the robot and the provenance, not recorded
  const std::string file = seed("excitation_json/puma560_h2.json");
  const UpgradeOutcome design = upgradeDocument({file, ""});
  EXPECT_EQ(design.from, 1);
  EXPECT_EQ(design.document["schema_version"], kExcitationDocument.schema_version);
  EXPECT_TRUE(design.document["payload_link"].is_null());
  EXPECT_FALSE(design.document.contains("model"));  // it was the robot's name
  const FourierSeries before = excitationDesignFrom(parseJson(readFile(file), file), file, 6);
  const FourierSeries after = excitationDesignFrom(design.document, "upgraded", 6);
  EXPECT_EQ(after.a, before.a);
  EXPECT_EQ(after.offset, before.offset);
  // Version 5's stand orientations: absent (none were chosen then), said, and read as none.
  EXPECT_FALSE(design.document.contains("stand"));
  bool said = false;
  for (const std::string& note : design.notes) said = said || note.find("stand") != note.npos;
  EXPECT_TRUE(said);
  EXPECT_TRUE(excitationStandTiltsFrom(design.document, "upgraded").empty());
}

// thresholds.json 1 to 4 -> 5: the states and regimes they lacked are null, and they read back.
TEST(Upgrade, OlderThresholdsGetNullStatesAndRegimes) {
  const nlohmann::json base = {{"schema_version", kMonitorThresholdsDocument.schema_version},
                               {"kind", kMonitorThresholdsDocument.kind},
                               {"robot", "puma560"},
                               {"joints", {"j1", "j2"}},
                               {"residual", "observer"},
                               {"gain", {100.0, 50.0}},
                               {"thresholds", {2.5, 0.75}},
                               {"source", "calibration clean.csv"},
                               {"false_alarms_per_hour", 0.5}};
  for (int version = 1; version < kMonitorThresholdsDocument.schema_version; ++version) {
    nlohmann::json older = base;  // version 1's keys; then what each version added, as written
    older["schema_version"] = version;
    if (version >= 2) older["rest_velocity"] = older["thresholds_at_rest"] = nullptr;
    if (version >= 3) older["moving_regimes"] = nullptr;
    const UpgradeOutcome up = upgradeDocument({asFile("thresholds_old.json", older), ""});
    EXPECT_EQ(up.from, version);
    EXPECT_TRUE(up.document["moving_regimes"].is_null());
    EXPECT_TRUE(up.document["thresholds_at_rest"].is_null()) << version;
    const MonitorThresholds t = readMonitorThresholds(asFile("thresholds_new.json", up.document));
    EXPECT_EQ(t.schema_version, kMonitorThresholdsDocument.schema_version);
    EXPECT_EQ(t.values, Eigen::Vector2d(2.5, 0.75));
    EXPECT_EQ(t.values_at_rest.size(), 0);
  }
}

// The documents no command reads back are upgraded for their other readers: a version's renamed
// keys renamed, one note per later version whose additions they lack, the result current and
// upgraded again unchanged.
TEST(Upgrade, DocumentsNoCommandReadsBackUpgradeToo) {
  // prediction.json 1: the per-joint errors under their old names, at the top and in the raw
  // comparison.
  const nlohmann::json prediction = {
      {"schema_version", 1},
      {"kind", kPredictionDocument.kind},
      {"relative_error", 0.01},
      {"torque_rms", {0.1, 0.2}},
      {"raw_measurement", {{"torque_rms", {0.3, 0.4}}, {"normalised_rms", {0.5, 0.6}}}}};
  const UpgradeOutcome p = upgradeDocument({asFile("prediction_v1.json", prediction), ""});
  EXPECT_EQ(p.to, kPredictionDocument.schema_version);
  EXPECT_EQ(p.document["residual_rms"], nlohmann::json({0.1, 0.2}));
  EXPECT_FALSE(p.document.contains("torque_rms"));
  EXPECT_EQ(p.document["raw_measurement"]["joint_relative_error"], nlohmann::json({0.5, 0.6}));
  EXPECT_EQ(p.document["relative_error"], 0.01);
  // Three renames, then versions 3, 4, 5 and 6's additions not recorded.
  EXPECT_EQ(p.notes.size(), 7u);
  EXPECT_EQ(p.notes[3],
            "version 3 added rest_velocity and at_rest (the prediction at rest): not recorded "
            "here, left absent");
  // prepare.json 1 named its one table; version 2 lists them.
  const nlohmann::json prepare = {
      {"schema_version", 1}, {"kind", kPrepareDocument.kind}, {"sources", {{"table", "log.csv"}}}};
  const UpgradeOutcome q = upgradeDocument({asFile("prepare_v1.json", prepare), ""});
  EXPECT_EQ(q.document["sources"]["tables"], nlohmann::json({"log.csv"}));
  EXPECT_FALSE(q.document["sources"].contains("table"));
  // Every kind, from its first version: current, and again unchanged.
  for (const DocumentType* type :
       {&kPredictionDocument, &kPayloadDocument, &kPayloadBodyDocument, &kMonitorDocument,
        &kAuditDocument, &kStudyDocument, &kRefineDocument, &kPrepareDocument,
        &kIdentifiabilityDocument, &kDemoDocument, &kFloatingPrepareDocument,
        &kFloatingIdentificationDocument}) {
    const nlohmann::json first = {{"schema_version", 1}, {"kind", type->kind}};
    const UpgradeOutcome up = upgradeDocument({asFile("first.json", first), ""});
    EXPECT_EQ(up.from, 1) << type->kind;
    EXPECT_EQ(up.document["schema_version"], type->schema_version) << type->kind;
    // A note per later version; prediction.json 2 only renamed keys, which this one lacks.
    const int renames_only = type == &kPredictionDocument ? 1 : 0;
    EXPECT_EQ(up.notes.size(), static_cast<std::size_t>(type->schema_version - 1 - renames_only))
        << type->kind;
    const UpgradeOutcome again = upgradeDocument({asFile("again.json", up.document), ""});
    EXPECT_EQ(again.from, again.to) << type->kind;
    EXPECT_EQ(again.document, up.document) << type->kind;
  }
}

TEST(Upgrade, RefusesLaterVersionsOtherKindsAndLostRobots) {
  nlohmann::json later = parseJson(readFile(seed("search_json/ga_search.json")), "s");
  later["schema_version"] = kSearchDocument.schema_version + 1;
  try {
    upgradeDocument({asFile("later.json", later), ""});
    ADD_FAILURE() << "a later version was upgraded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("written by a newer dynid"), std::string::npos);
  }
  const nlohmann::json checkpoint = {{"schema_version", 1}, {"kind", "dynid.search_checkpoint"}};
  try {
    upgradeDocument({asFile("checkpoint.json", checkpoint), ""});
    ADD_FAILURE() << "a checkpoint (one version only) was upgraded";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("no earlier version"), std::string::npos) << e.what();
  }
  nlohmann::json lost = parseJson(readFile(seed("estimate_json/puma560_ols.json")), "e");
  lost["robot_spec"] = "gone.urdf";
  try {
    upgradeDocument({asFile("lost.json", lost), ""});
    ADD_FAILURE() << "an estimate without its robot was upgraded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'gone.urdf'; give it with `robot`"), std::string::npos)
        << e.what();
  }
  // Given, the robot is embedded from there.
  EXPECT_EQ(
      upgradeDocument({asFile("lost.json", lost), "puma560"}).document["model_source"]["spec"],
      "puma560");
}

}  // namespace
}  // namespace dynid
