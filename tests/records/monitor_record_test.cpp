// thresholds.json read back (analysis/records/monitor_record.hpp), as reports/monitor_report
// writes it (monitorThresholdsJson): the thresholds, their gain and residual, and the refusals.
#include "analysis/records/monitor_record.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

nlohmann::json thresholdsDocument() {
  return {{"schema_version", kMonitorThresholdsDocument.schema_version},
          {"kind", kMonitorThresholdsDocument.kind},
          {"robot", "puma560"},
          {"joints", {"j1", "j2"}},
          {"residual", "direct"},
          {"gain", {100.0, 50.0}},
          {"thresholds", {2.5, 0.75}},
          {"source", "calibration clean.csv"},
          {"false_alarms_per_hour", 0.5},
          {"calibration_rms", {0.5, 0.125}},
          {"calibration_max", {2.0, 0.5}},
          {"calibration_seconds", 60.0},
          {"rest_velocity", {0.003, 0.004}},
          {"thresholds_at_rest", {0.25, 0.125}},
          {"calibration_rest_rms", {0.05, 0.025}},
          {"rest_seconds", 21.5}};
}

std::string written(const std::string& name, const nlohmann::json& document) {
  const std::string path = test::tempPath(name);
  writeFileAtomically(path, document.dump(2));
  return path;
}

TEST(MonitorRecord, ReadsTheThresholdsTheirGainAndResidual) {
  const std::string path = written("thresholds_ok.json", thresholdsDocument());
  const MonitorThresholds t = readMonitorThresholds(path);
  EXPECT_EQ(t.robot, "puma560");
  EXPECT_EQ(t.joint_names, (std::vector<std::string>{"j1", "j2"}));
  EXPECT_EQ(t.residual, MonitorResidual::kDirect);
  EXPECT_EQ(t.gain, Eigen::Vector2d(100.0, 50.0));
  EXPECT_EQ(t.values, Eigen::Vector2d(2.5, 0.75));
  EXPECT_EQ(t.false_alarms_per_hour, 0.5);
  EXPECT_EQ(t.source, "thresholds " + path);  // where this monitor's thresholds came from
  EXPECT_EQ(t.rest_velocity, Eigen::Vector2d(0.003, 0.004));
  EXPECT_EQ(t.values_at_rest, Eigen::Vector2d(0.25, 0.125));
  EXPECT_EQ(t.rest_seconds, 21.5);
}

TEST(MonitorRecord, ReadsVersion1AndThresholdsWithoutRestAsMovingOnly) {
  // Version 1 (before the arm states): its keys only, no rest state.
  nlohmann::json v1 = thresholdsDocument();
  v1["schema_version"] = 1;
  for (const char* key :
       {"rest_velocity", "thresholds_at_rest", "calibration_rest_rms", "rest_seconds"})
    v1.erase(key);
  MonitorThresholds t = readMonitorThresholds(written("thresholds_v1.json", v1));
  EXPECT_EQ(t.values, Eigen::Vector2d(2.5, 0.75));
  EXPECT_EQ(t.rest_velocity.size(), 0);
  EXPECT_EQ(t.values_at_rest.size(), 0);
  v1["rest_velocity"] = {0.003, 0.004};  // a version 2 key in a version 1 file
  EXPECT_THROW(readMonitorThresholds(written("thresholds_v1_rest.json", v1)), ParseError);
  // Version 2 from a calibration that never held its pose: rest velocities, no thresholds at rest.
  nlohmann::json d = thresholdsDocument();
  d["thresholds_at_rest"] = nullptr;
  d.erase("rest_seconds");
  d.erase("calibration_rest_rms");
  t = readMonitorThresholds(written("thresholds_no_rest.json", d));
  EXPECT_EQ(t.rest_velocity.size(), 2);
  EXPECT_EQ(t.values_at_rest.size(), 0);
}

TEST(MonitorRecord, RefusesWhatNoMonitorWrote) {
  const auto field = [](const char* name, const nlohmann::json& document) {
    try {
      readMonitorThresholds(written(name, document));
    } catch (const ParseError& e) {
      return e.element();
    }
    return std::string("accepted");
  };
  nlohmann::json d = thresholdsDocument();
  d["residual"] = "both";
  EXPECT_EQ(field("thresholds_residual.json", d), "residual");
  d = thresholdsDocument();
  d["thresholds"] = {2.5, -1.0};
  EXPECT_EQ(field("thresholds_negative.json", d), "thresholds[1]");
  d = thresholdsDocument();
  d["gain"] = {100.0};
  EXPECT_NE(field("thresholds_gain.json", d), "accepted");
  d = thresholdsDocument();
  d["extra"] = 1;
  EXPECT_NE(field("thresholds_extra.json", d), "accepted");
  d = thresholdsDocument();
  d["thresholds_at_rest"] = {0.25, 0.0};
  EXPECT_EQ(field("thresholds_at_rest_zero.json", d), "thresholds_at_rest[1]");
  d = thresholdsDocument();
  d["rest_velocity"] = {0.003, -1.0};
  EXPECT_EQ(field("thresholds_rest_velocity.json", d), "rest_velocity[1]");
  d = thresholdsDocument();
  d["kind"] = "dynid.estimate";
  EXPECT_NE(field("thresholds_kind.json", d), "accepted");
}

}  // namespace
}  // namespace dynid
