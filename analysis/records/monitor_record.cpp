#include "analysis/records/monitor_record.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "analysis/records/document.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

namespace {

/// The document's schema_version when it is an integer from 1 to `current`, else `current` (the
/// header check then names it).
int documentVersion(const nlohmann::json& document, int current) {
  if (document.is_object() && document.contains("schema_version") &&
      document["schema_version"].is_number_integer() && document["schema_version"] >= 1 &&
      document["schema_version"] < current)
    return document["schema_version"].get<int>();
  return current;
}

/// Version 2's arm states: the rest velocities and, when the calibration held a pose, the
/// thresholds at rest (null otherwise).
void readRestThresholds(const JsonReader& read, const nlohmann::json& document, long n,
                        MonitorThresholds& out) {
  const nlohmann::json& rest = read.field(document, "", "rest_velocity");
  if (rest.is_null()) return;  // thresholds without arm states (read from version 1)
  out.rest_velocity = read.vector(rest, "rest_velocity", n);
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(out.rest_velocity[j] >= 0.0) || !std::isfinite(out.rest_velocity[j]))
      read.fail(JsonReader::index("rest_velocity", j), "expected a finite number >= 0");
  const nlohmann::json& at_rest = read.field(document, "", "thresholds_at_rest");
  if (at_rest.is_null()) return;
  out.values_at_rest = read.vector(at_rest, "thresholds_at_rest", n);
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(out.values_at_rest[j] > 0.0) || !std::isfinite(out.values_at_rest[j]))
      read.fail(JsonReader::index("thresholds_at_rest", j), "expected a positive finite number");
  out.rest_seconds = read.number(document, "", "rest_seconds", 0.0, 1e12);
}

}  // namespace

MonitorThresholds readMonitorThresholds(const std::string& file) {
  const nlohmann::json document = parseJson(readFile(file), file);
  const JsonReader read(file);
  // Version 1 (before the arm states) is read as it is: no rest state.
  const int version = documentVersion(document, kMonitorThresholdsDocument.schema_version);
  read.header(document, version, kMonitorThresholdsDocument.kind);
  std::vector<std::string> keys = {"schema_version",
                                   "kind",
                                   "robot",
                                   "joints",
                                   "residual",
                                   "gain",
                                   "thresholds",
                                   "source",
                                   "false_alarms_per_hour",
                                   "calibration_rms",
                                   "calibration_max",
                                   "calibration_seconds"};
  if (version >= 2)
    keys.insert(keys.end(),
                {"rest_velocity", "thresholds_at_rest", "calibration_rest_rms", "rest_seconds"});
  read.onlyKeysIn(document, "", keys);
  MonitorThresholds out;
  out.robot = read.string(document, "", "robot");
  out.joint_names = read.strings(read.field(document, "", "joints"), "joints");
  const long n = static_cast<long>(out.joint_names.size());
  const std::string residual = read.string(document, "", "residual");
  if (residual != "observer" && residual != "direct")
    read.fail("residual", "expected observer or direct");
  out.residual = residual == "direct" ? MonitorResidual::kDirect : MonitorResidual::kObserver;
  out.gain = read.vector(read.field(document, "", "gain"), "gain", n);
  out.values = read.vector(read.field(document, "", "thresholds"), "thresholds", n);
  for (Eigen::Index j = 0; j < n; ++j) {
    if (!(out.values[j] > 0.0) || !std::isfinite(out.values[j]))
      read.fail(JsonReader::index("thresholds", j), "expected a positive finite number");
    if (!(out.gain[j] > 0.0) || !std::isfinite(out.gain[j]))
      read.fail(JsonReader::index("gain", j), "expected a positive finite number");
  }
  out.source = "thresholds " + file;
  if (version >= 2) readRestThresholds(read, document, n, out);
  if (document.contains("false_alarms_per_hour"))
    out.false_alarms_per_hour = read.number(document, "", "false_alarms_per_hour", 0.0, 1e9);
  return out;
}

}  // namespace dynid
