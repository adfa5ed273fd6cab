#include "analysis/records/monitor_record.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "analysis/records/document.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

MonitorThresholds readMonitorThresholds(const std::string& file) {
  const nlohmann::json document = parseJson(readFile(file), file);
  const JsonReader read(file);
  read.header(document, kMonitorThresholdsDocument.schema_version, kMonitorThresholdsDocument.kind);
  read.onlyKeys(
      document, "",
      {"schema_version", "kind", "robot", "joints", "residual", "gain", "thresholds", "source",
       "false_alarms_per_hour", "calibration_rms", "calibration_max", "calibration_seconds"});
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
  if (document.contains("false_alarms_per_hour"))
    out.false_alarms_per_hour = read.number(document, "", "false_alarms_per_hour", 0.0, 1e9);
  return out;
}

}  // namespace dynid
