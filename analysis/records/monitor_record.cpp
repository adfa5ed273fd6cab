#include "analysis/records/monitor_record.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

namespace {

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

/// Version 3's moving regimes (null: none): the scales (finite, >= 0) and, per joint, a threshold
/// per regime (positive, or null where the calibration had too little of it) and its time there.
void readMovingRegimes(const JsonReader& read, const nlohmann::json& document, long n,
                       MonitorThresholds& out) {
  const nlohmann::json& regimes = read.field(document, "", "moving_regimes");
  if (regimes.is_null()) return;
  const std::string at = "moving_regimes";
  read.onlyKeysIn(regimes, at,
                  std::vector<std::string>{"regimes", "speed_scale", "acceleration_scale",
                                           "thresholds", "seconds"});
  const std::vector<std::string> names =
      read.strings(read.field(regimes, at, "regimes"), at + ".regimes");
  if (names != std::vector<std::string>(kMovingRegimeNames.begin(), kMovingRegimeNames.end()))
    read.fail(at + ".regimes", "expected the regimes dynid writes, in its order");
  const auto scale = [&](const char* key) {
    const std::string path = at + "." + key;
    Eigen::VectorXd v = read.vector(read.field(regimes, at, key), path, n);
    for (Eigen::Index j = 0; j < n; ++j)
      if (!(v[j] >= 0.0)) read.fail(JsonReader::index(path, j), "expected a number >= 0");
    return v;
  };
  out.speed_scale = scale("speed_scale");
  out.acceleration_scale = scale("acceleration_scale");
  out.values_by_regime = Eigen::MatrixXd::Zero(n, kMovingRegimes);
  out.regime_seconds = Eigen::MatrixXd::Zero(n, kMovingRegimes);
  const nlohmann::json& thresholds = read.field(regimes, at, "thresholds");
  const nlohmann::json& seconds = read.field(regimes, at, "seconds");
  for (const auto* table : {&thresholds, &seconds}) {
    const std::string path = at + (table == &thresholds ? ".thresholds" : ".seconds");
    read.array(*table, path);
    if (static_cast<long>(table->size()) != n)
      read.fail(path, "expected one row per joint (" + std::to_string(n) + ")");
    for (long j = 0; j < n; ++j) {
      const std::string row = JsonReader::index(path, static_cast<std::size_t>(j));
      const nlohmann::json& values = read.array((*table)[static_cast<std::size_t>(j)], row);
      if (values.size() != kMovingRegimes)
        read.fail(row, "expected " + std::to_string(kMovingRegimes) + " entries, one per regime");
      for (int c = 0; c < kMovingRegimes; ++c) {
        const nlohmann::json& v = values[static_cast<std::size_t>(c)];
        const std::string cell = JsonReader::index(row, static_cast<std::size_t>(c));
        if (table == &thresholds && !v.is_null())
          out.values_by_regime(j, c) = read.number(v, cell, 1e-300, 1e300);
        else if (table == &seconds)
          out.regime_seconds(j, c) = read.number(v, cell, 0.0, 1e12);
      }
    }
  }
}

}  // namespace

MonitorThresholds readMonitorThresholds(const std::string& file) {
  const nlohmann::json document = parseJson(readFile(file), file);
  const JsonReader read(file);
  // Version 1 (before the arm states) is read as it is: no rest state; version 2 (before the
  // moving regimes): one moving threshold per joint.
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
  if (version >= 3) keys.push_back("moving_regimes");
  if (version >= 4) keys.insert(keys.end(), {"model", "model_source"});
  if (version >= 5) keys.push_back("provenance");
  read.onlyKeysIn(document, "", keys);
  // The arm they were set for, embedded for the record: checked for form, not used (the
  // monitor's own --arm is compared by its joints, residual and gain).
  if (document.contains("model")) read.object(document["model"], "model");
  if (document.contains("model_source"))
    modelSourceFrom(document["model_source"], file, "model_source");
  MonitorThresholds out;
  out.schema_version = version;
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
  if (version >= 3) readMovingRegimes(read, document, n, out);
  if (document.contains("false_alarms_per_hour"))
    out.false_alarms_per_hour = read.number(document, "", "false_alarms_per_hour", 0.0, 1e9);
  return out;
}

}  // namespace dynid
