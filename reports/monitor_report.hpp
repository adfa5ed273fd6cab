// What `dynid monitor` writes: monitor.json (the thresholds, every event, the residuals' statistics
// and, with a ground truth, the detection score), thresholds.json (read back by --thresholds),
// report.md / report.html (the verdict, the events, the thresholds) and residuals.svg (each joint's
// residual envelope against its thresholds, the events shaded); and the events as JSON lines
// while it runs.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/monitor/monitor.hpp"

namespace dynid {

/// One event as a JSON object (start, end, joints 1-based, peak, energy, open).
nlohmann::json monitorEventJson(const MonitorEvent& event);
/// thresholds.json.
nlohmann::json monitorThresholdsJson(const MonitorThresholds& thresholds);
/// monitor.json.
nlohmann::json monitorJson(const MonitorOutcome& outcome);
/// Writes monitor.json, thresholds.json, the report and its figure (when gnuplot works) into
/// `dir` as one set. Returns the console summary.
std::string writeMonitor(const std::string& dir, const MonitorOutcome& outcome,
                         const std::string& data_file);
/// The console summary alone (the stdin mode without --out).
std::string monitorSummary(const MonitorOutcome& outcome);

}  // namespace dynid
