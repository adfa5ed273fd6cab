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
          {"calibration_seconds", 60.0}};
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
  d["kind"] = "dynid.estimate";
  EXPECT_NE(field("thresholds_kind.json", d), "accepted");
}

}  // namespace
}  // namespace dynid
