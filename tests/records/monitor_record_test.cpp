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
          {"rest_seconds", 21.5},
          {"moving_regimes",
           {{"regimes", kMovingRegimeNames},
            {"speed_scale", {1.5, 0.0}},
            {"acceleration_scale", {4.0, 0.0}},
            {"thresholds",
             {{5.0, 6.0, 1.25, 2.0, 2.5, nullptr},
              {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr}}},
            {"seconds", {{3.0, 2.5, 20.0, 10.0, 8.0, 1.5}, {0.0, 0.0, 50.0, 0.0, 0.0, 0.0}}}}}};
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
  // The moving regimes: a threshold per regime where the calibration had enough of it (0: none).
  EXPECT_EQ(t.speed_scale, Eigen::Vector2d(1.5, 0.0));
  EXPECT_EQ(t.acceleration_scale, Eigen::Vector2d(4.0, 0.0));
  ASSERT_EQ(t.values_by_regime.rows(), 2);
  ASSERT_EQ(t.values_by_regime.cols(), kMovingRegimes);
  EXPECT_EQ(t.values_by_regime(0, 0), 5.0);
  EXPECT_EQ(t.values_by_regime(0, 2), 1.25);
  EXPECT_EQ(t.values_by_regime(0, 5), 0.0);
  EXPECT_EQ(t.values_by_regime.row(1).norm(), 0.0);
  EXPECT_EQ(t.regime_seconds(0, 2), 20.0);
  EXPECT_EQ(t.regime_seconds(1, 2), 50.0);
}

TEST(MonitorRecord, ReadsVersion2AsOneMovingThresholdPerJoint) {
  nlohmann::json v2 = thresholdsDocument();
  v2["schema_version"] = 2;
  v2.erase("moving_regimes");
  MonitorThresholds t = readMonitorThresholds(written("thresholds_v2.json", v2));
  EXPECT_EQ(t.values, Eigen::Vector2d(2.5, 0.75));
  EXPECT_EQ(t.values_at_rest, Eigen::Vector2d(0.25, 0.125));  // the arm states are kept
  EXPECT_EQ(t.values_by_regime.size(), 0);
  EXPECT_EQ(t.speed_scale.size(), 0);
  v2["moving_regimes"] = nullptr;  // a version 3 key in a version 2 file
  EXPECT_THROW(readMonitorThresholds(written("thresholds_v2_regimes.json", v2)), ParseError);
  // Version 3 from thresholds without regimes: null.
  nlohmann::json d = thresholdsDocument();
  d["moving_regimes"] = nullptr;
  t = readMonitorThresholds(written("thresholds_no_regimes.json", d));
  EXPECT_EQ(t.values_by_regime.size(), 0);
}

TEST(MonitorRecord, ReadsVersion1AndThresholdsWithoutRestAsMovingOnly) {
  // Version 1 (before the arm states): its keys only, no rest state.
  nlohmann::json v1 = thresholdsDocument();
  v1["schema_version"] = 1;
  for (const char* key : {"rest_velocity", "thresholds_at_rest", "calibration_rest_rms",
                          "rest_seconds", "moving_regimes"})
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
  d["moving_regimes"]["thresholds"][0] = {5.0, 6.0, 1.25};
  EXPECT_EQ(field("thresholds_regimes_row.json", d), "moving_regimes.thresholds[0]");
  d = thresholdsDocument();
  d["moving_regimes"]["thresholds"][0][2] = 0.0;
  EXPECT_EQ(field("thresholds_regimes_zero.json", d), "moving_regimes.thresholds[0][2]");
  d = thresholdsDocument();
  d["moving_regimes"]["seconds"][1][2] = nullptr;
  EXPECT_EQ(field("thresholds_regimes_seconds.json", d), "moving_regimes.seconds[1][2]");
  d = thresholdsDocument();
  d["moving_regimes"]["regimes"][0] = "reversal";
  EXPECT_EQ(field("thresholds_regimes_names.json", d), "moving_regimes.regimes");
  d = thresholdsDocument();
  d["moving_regimes"]["speed_scale"] = {1.5, -1.0};
  EXPECT_EQ(field("thresholds_regimes_scale.json", d), "moving_regimes.speed_scale[1]");
  d = thresholdsDocument();
  d.erase("moving_regimes");
  EXPECT_EQ(field("thresholds_regimes_missing.json", d), "moving_regimes");
  d = thresholdsDocument();
  d["kind"] = "dynid.estimate";
  EXPECT_NE(field("thresholds_kind.json", d), "accepted");
}

}  // namespace
}  // namespace dynid
