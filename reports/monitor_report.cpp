#include "reports/monitor_report.hpp"

#include <algorithm>
#include <sstream>

#include "analysis/monitor/regimes.hpp"
#include "analysis/monitor/states.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"
#include "reports/plot_script.hpp"

namespace dynid {

using nlohmann::json;

namespace {
const char* residualName(MonitorResidual r) {
  return r == MonitorResidual::kDirect ? "direct" : "observer";
}

/// "at rest", "moving" or "moving, <the peak joint's regime>".
std::string armState(const MonitorEvent& e) {
  if (e.at_rest) return "at rest";
  if (e.peak_regime < 0) return "moving";
  std::string regime = kMovingRegimeNames[static_cast<std::size_t>(e.peak_regime)];
  std::replace(regime.begin(), regime.end(), '_', ' ');
  return "moving, " + regime;
}

std::string jointList(const std::vector<int>& joints) {
  std::string out;
  for (int j : joints) out += (out.empty() ? "" : ", ") + std::to_string(j + 1);
  return out;
}

/// Why the thresholds are where they are: the rate asked for, and what the calibration confirms.
std::string confidenceText(const MonitorThresholds& t) {
  const std::optional<CalibrationConfidence> c = calibrationConfidence(t);
  if (!c) return "";
  std::string out = "The thresholds are set for " + formatNumber(t.false_alarms_per_hour, 3) +
                    " false alarms per hour; " + formatNumber(c->seconds, 4) +
                    " s of calibration confirm a rate no lower than " +
                    formatNumber(c->confirmed_per_hour, 3) +
                    " per hour (no alarm in T seconds: below 3 / T at 95 %)";
  if (c->extrapolated)
    out += ", and " + formatNumber(t.false_alarms_per_hour, 3) + " per hour would need " +
           formatNumber(c->needed_seconds / 3600.0, 3) +
           " h of clean calibration: below that the thresholds rest on the residual's Gaussian "
           "tail, not on the data";
  return out + ".";
}

/// Why a resting arm is judged as it is: thresholds at rest, or none (and what gives them).
std::string statesText(const MonitorOutcome& o) {
  const MonitorThresholds& t = o.thresholds;
  if (t.rest_velocity.size() == 0) return "";
  if (t.values_at_rest.size() == 0)
    return "The calibration held its pose " + formatNumber(t.rest_seconds, 3) + " s (" +
           formatNumber(kMinRestSeconds, 3) +
           " s are needed): the moving thresholds apply at rest too, so a push at rest must "
           "exceed them; calibrate on a log with stops to judge a resting arm by its noise at "
           "rest.";
  const Eigen::ArrayXd ratio = t.values.array() / t.values_at_rest.array();
  // No alarm in T s at rest bounds the rate at rest below 3 / T (a file may say T = 0).
  const std::string confirmed = t.rest_seconds > 0.0
                                    ? " (which confirm a rate no lower than " +
                                          formatNumber(3.0 / t.rest_seconds * 3600.0, 3) +
                                          " per hour at rest)"
                                    : "";
  return "At rest (every joint within its rest velocity, measured on the calibration; within them "
         "the model's friction is the static friction's point value, not Fc sign(dq)) a push is "
         "the residual's change from its level at rest once it has lasted " +
         formatNumber(kRestPersistSeconds, 3) + " s; while the arm settles (its first " +
         formatNumber(kRestSettleSeconds, 3) +
         " s at rest) or stirs short of leaving rest, only a change that drives a stirring joint "
         "counts (friction and a commanded start work against the motion). It is judged by "
         "thresholds at rest learnt from the calibration's " +
         formatNumber(t.rest_seconds, 3) + " s settled at rest" + confirmed + ", " +
         formatNumber(ratio.minCoeff(), 3) + " to " + formatNumber(ratio.maxCoeff(), 3) +
         " times below the moving ones; the arm " + "was settled at rest " +
         formatNumber(o.rest_seconds, 4) + " s of the " + formatNumber(o.seconds, 4) +
         " s watched.";
}

/// Why a moving joint is judged as it is: its regime's threshold where the calibration had enough
/// of the regime, else its single moving threshold.
std::string regimesText(const MonitorThresholds& t) {
  if (t.values_by_regime.size() == 0) return "";
  const Eigen::Index n = t.values.size();
  int own = 0;
  double low = 1e300, high = 0.0;
  for (Eigen::Index j = 0; j < n; ++j)
    for (int c = 0; c < kMovingRegimes; ++c)
      if (t.values_by_regime(j, c) > 0.0) {
        ++own;
        low = std::min(low, t.values_by_regime(j, c) / t.values[j]);
        high = std::max(high, t.values_by_regime(j, c) / t.values[j]);
      }
  std::string out =
      "Moving, each joint is judged by its regime: slow (below " +
      formatNumber(100.0 * kSlowSpeedShare, 3) +
      " % of its speed on the calibration, near a reversal), cruising or fast (above " +
      formatNumber(100.0 * kFastSpeedShare, 3) + " %), accelerating or not (above " +
      formatNumber(100.0 * kAcceleratingShare, 3) + " % of its acceleration); a regime has " +
      "a threshold of its own where the calibration spent " + formatNumber(kMinRegimeSeconds, 3) +
      " s in it, ";
  if (own == 0)
    return out + "which none of its " + std::to_string(n * kMovingRegimes) +
           " did: the single moving threshold applies throughout (calibrate on a longer log "
           "for thresholds that follow the speed and the acceleration).";
  return out + "which " + std::to_string(own) + " of " + std::to_string(n * kMovingRegimes) +
         " did, at " + formatNumber(low, 3) + " to " + formatNumber(high, 3) +
         " times the joint's single moving threshold (the others use it).";
}

std::string verdict(const MonitorOutcome& o) {
  std::ostringstream s;
  s << o.events.size() << (o.events.size() == 1 ? " event" : " events") << " in "
    << formatNumber(o.seconds, 4) << " s of " << o.robot_spec << " (" << o.samples
    << " samples), the " << residualName(o.thresholds.residual) << " residual against thresholds "
    << "from " << o.thresholds.source << ".";
  if (const std::string c = confidenceText(o.thresholds); !c.empty()) s << " " << c;
  if (const std::string c = statesText(o); !c.empty()) s << " " << c;
  if (const std::string c = regimesText(o.thresholds); !c.empty()) s << " " << c;
  if (o.interrupted) s << " Stopped early: the events so far.";
  if (const auto& t = o.truth) {
    s << " Against the ground truth: " << t->detected << " of " << t->episodes
      << " disturbances detected within " << formatNumber(t->window * 1e3, 3) << " ms, "
      << t->false_alarms << " false alarm(s).";
  }
  return s.str();
}

/// The report's verdict box: what was watched, what was found, how it scores, what next.
std::vector<std::pair<std::string, std::string>> verdictBox(const MonitorOutcome& o) {
  std::vector<int> joints;
  for (const MonitorEvent& e : o.events)
    for (int j : e.joints)
      if (std::find(joints.begin(), joints.end(), j) == joints.end()) joints.push_back(j);
  std::sort(joints.begin(), joints.end());
  std::vector<std::pair<std::string, std::string>> box = {
      {"Watched", formatNumber(o.seconds, 4) + " s of " + o.robot_spec + " (" +
                      std::to_string(o.samples) + " samples), the " +
                      residualName(o.thresholds.residual) + " residual" +
                      (o.interrupted ? " (stopped early)" : "")},
      {"Found", o.events.empty() ? "no event: every residual stayed within its threshold"
                                 : std::to_string(o.events.size()) +
                                       (o.events.size() == 1 ? " event" : " events") +
                                       " on joints " + jointList(joints)},
      {"Thresholds", "from " + o.thresholds.source}};
  if (const auto& t = o.truth)
    box.push_back({"Against the truth", std::to_string(t->detected) + " of " +
                                            std::to_string(t->episodes) +
                                            " disturbances detected, " +
                                            std::to_string(t->false_alarms) + " false alarm(s)"});
  box.push_back(
      {"Next",
       o.events.empty()
           ? "none needed; if pushes went unseen, lower the thresholds"
           : "look at the events below; false alarms on free motion mean the "
             "model or the thresholds need a refit (dynid monitor --calibration on a clean log)"});
  return box;
}

/// Each joint's residual envelope (min and max per bucket), its thresholds and the events.
std::optional<std::string> residualFigure(const MonitorOutcome& o) {
  const bool direct = o.thresholds.residual == MonitorResidual::kDirect;
  const ResidualEnvelope& env = direct ? o.direct_envelope : o.observer_envelope;
  const int n = static_cast<int>(o.thresholds.values.size());
  if (env.count() == 0 || n == 0) return std::nullopt;
  const Eigen::VectorXd t = env.time();
  const Eigen::MatrixXd low = env.low(), high = env.high();
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 900," << 150 * n + 60 << " font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout " << n << ",1\nset key top right horizontal\nset grid\n"
    << "set lmargin 10\n";
  for (int j = 0; j < n; ++j) {
    PlotRows data;
    for (Eigen::Index k = 0; k < t.size(); ++k) data.append({t[k], low(j, k), high(j, k)});
    s << "$r" << j << " << EOD\n" << data << "EOD\n";
    s << "unset object\n";
    int object = 1;
    for (const MonitorEvent& e : o.events)
      if (object < 200)
        s << "set object " << object++ << " rect from " << e.start << ",graph 0 to "
          << std::max(e.end, e.start + 1e-3) << ",graph 1 fc rgb '#ffd8a8' fs solid 0.6 noborder "
          << "behind\n";
    s << "set ylabel 'r" << j + 1 << " [N m]'\n";
    if (j + 1 == n)
      s << "set xlabel 't [s]'\n";
    else
      s << "unset xlabel\n";
    const double th = o.thresholds.values[j];
    s << "plot $r" << j << " using 1:2:3 with filledcurves lc rgb '#4477aa' title 'residual', "
      << th << " with lines lw 1.2 dt 2 lc rgb '#cc3311' title 'threshold', " << -th
      << " with lines lw 1.2 dt 2 lc rgb '#cc3311' notitle\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s);
}
}  // namespace

/// Moving, each joint's threshold per regime and the calibration's time in it.
DocumentTable regimesTable(const MonitorThresholds& t) {
  DocumentTable table;
  table.header = {"joint"};
  for (const char* name : kMovingRegimeNames) table.header.push_back(name);
  for (Eigen::Index j = 0; j < t.values.size(); ++j) {
    std::vector<std::string> row = {std::to_string(j + 1)};
    for (int c = 0; c < kMovingRegimes; ++c) {
      const double seconds = t.regime_seconds.size() > 0 ? t.regime_seconds(j, c) : 0.0;
      row.push_back((t.values_by_regime(j, c) > 0.0 ? formatNumber(t.values_by_regime(j, c), 4)
                                                    : std::string("-")) +
                    " (" + formatNumber(seconds, 3) + " s)");
    }
    table.rows.push_back(row);
  }
  table.caption =
      "Moving thresholds per regime [N m] and the calibration's time in each; '-': less than " +
      formatNumber(kMinRegimeSeconds, 3) +
      " s, the joint's single moving threshold applies there. Slow: below " +
      formatNumber(100.0 * kSlowSpeedShare, 3) + " % of the joint's speed scale (" +
      "the 95th percentile of its speed on the calibration); fast: above " +
      formatNumber(100.0 * kFastSpeedShare, 3) + " %; accelerating: above " +
      formatNumber(100.0 * kAcceleratingShare, 3) +
      " % of its acceleration scale. A regime is kept " +
      formatNumber(kRegimeMemorySeconds * 1e3, 3) +
      " ms after the joint left it (the observer's lag).";
  return table;
}

json monitorEventJson(const MonitorEvent& e) {
  json joints = json::array();
  for (int j : e.joints) joints.push_back(j + 1);
  return {{"start", e.start},
          {"end", e.end},
          {"joints", joints},
          {"peak_joint", e.peak_joint + 1},
          {"contact_link", e.contact_link + 1},
          {"peak", e.peak},
          {"peak_time", e.peak_time},
          {"energy", e.energy},
          {"open", e.open},
          {"state", e.at_rest ? "rest" : "moving"},
          {"regime", e.peak_regime >= 0
                         ? json(kMovingRegimeNames[static_cast<std::size_t>(e.peak_regime)])
                         : json(nullptr)}};
}

/// Version 3's moving regimes: the scales, and per joint one threshold per regime (null where the
/// calibration spent too little time in it) and that time; null without regimes.
json movingRegimesJson(const MonitorThresholds& t) {
  if (t.values_by_regime.size() == 0) return nullptr;
  json thresholds = json::array(), seconds = json::array();
  for (Eigen::Index j = 0; j < t.values_by_regime.rows(); ++j) {
    json u = json::array(), s = json::array();
    for (int c = 0; c < kMovingRegimes; ++c) {
      u.push_back(t.values_by_regime(j, c) > 0.0 ? json(t.values_by_regime(j, c)) : json(nullptr));
      s.push_back(t.regime_seconds.size() > 0 ? t.regime_seconds(j, c) : 0.0);
    }
    thresholds.push_back(u);
    seconds.push_back(s);
  }
  return {{"regimes", kMovingRegimeNames},
          {"speed_scale", numbersOrNull(t.speed_scale)},
          {"acceleration_scale", numbersOrNull(t.acceleration_scale)},
          {"thresholds", thresholds},
          {"seconds", seconds}};
}

json monitorThresholdsJson(const MonitorThresholds& t) {
  json out = {{"schema_version", kMonitorThresholdsDocument.schema_version},
              {"kind", kMonitorThresholdsDocument.kind},
              {"robot", t.robot},
              {"joints", t.joint_names},
              {"residual", residualName(t.residual)},
              {"gain", numbersOrNull(t.gain)},
              {"thresholds", numbersOrNull(t.values)},
              {"source", t.source},
              {"false_alarms_per_hour", t.false_alarms_per_hour}};
  if (t.calibration_rms.size() > 0) {
    out["calibration_rms"] = numbersOrNull(t.calibration_rms);
    out["calibration_max"] = numbersOrNull(t.calibration_max);
    out["calibration_seconds"] = t.calibration_seconds;
  }
  out["rest_velocity"] =
      t.rest_velocity.size() > 0 ? numbersOrNull(t.rest_velocity) : json(nullptr);
  out["thresholds_at_rest"] =
      t.values_at_rest.size() > 0 ? numbersOrNull(t.values_at_rest) : json(nullptr);
  if (t.values_at_rest.size() > 0) {
    out["rest_seconds"] = t.rest_seconds;
    if (t.calibration_rest_rms.size() > 0)
      out["calibration_rest_rms"] = numbersOrNull(t.calibration_rest_rms);
  }
  out["moving_regimes"] = movingRegimesJson(t);
  return out;
}

json monitorJson(const MonitorOutcome& o) {
  json events = json::array();
  for (const MonitorEvent& e : o.events) events.push_back(monitorEventJson(e));
  json out = {{"schema_version", kMonitorDocument.schema_version},
              {"kind", kMonitorDocument.kind},
              {"robot", o.model.name},
              {"robot_spec", o.robot_spec},
              {"samples", o.samples},
              {"seconds", o.seconds},
              {"restarts", o.restarts},
              {"interrupted", o.interrupted},
              {"thresholds", monitorThresholdsJson(o.thresholds)},
              {"events", events},
              {"observer_rms", numbersOrNull(o.observer_rms)},
              {"observer_max", numbersOrNull(o.observer_max)},
              {"warnings", o.warnings}};
  embedModel(out, o.model, o.source);
  if (const std::optional<CalibrationConfidence> c = calibrationConfidence(o.thresholds))
    out["calibration_confidence"] = {{"seconds", c->seconds},
                                     {"confirmed_false_alarms_per_hour", c->confirmed_per_hour},
                                     {"needed_seconds", c->needed_seconds},
                                     {"extrapolated", c->extrapolated}};
  if (o.has_direct) {
    out["direct_rms"] = numbersOrNull(o.direct_rms);
    out["direct_max"] = numbersOrNull(o.direct_max);
  }
  if (const auto& t = o.truth)
    out["truth"] = {
        {"episodes", t->episodes}, {"detected", t->detected}, {"false_alarms", t->false_alarms},
        {"window", t->window},     {"delays", t->delays},     {"missed_starts", t->missed_starts}};
  return out;
}

std::string monitorSummary(const MonitorOutcome& o) {
  std::ostringstream s;
  s << verdict(o) << "\n";
  for (const std::string& w : o.warnings) s << "warning: " << w << "\n";
  return s.str();
}

std::string writeMonitor(const std::string& dir, const MonitorOutcome& o,
                         const std::string& data_file) {
  Document report("Monitor: " + o.model.name);
  report.verdict(verdictBox(o));
  report.paragraph(verdict(o));
  report.bullets(o.warnings);
  report.heading("Events");
  DocumentTable events;
  events.header = {"start [s]",  "end [s]",    "arm",        "joints",
                   "peak [N m]", "peak joint", "contact on", "energy [J]"};
  for (const MonitorEvent& e : o.events)
    events.rows.push_back(
        {formatNumber(e.start, 6), formatNumber(e.end, 6) + (e.open ? " (open)" : ""), armState(e),
         jointList(e.joints), formatNumber(e.peak, 4), std::to_string(e.peak_joint + 1),
         "link " + std::to_string(e.contact_link + 1) + " or beyond", formatNumber(e.energy, 3)});
  events.caption =
      "An event starts at the first sample where a residual exceeds its threshold and "
      "ends when every residual has stayed below its threshold for the hold time. At rest, the "
      "residual is its change from its level at rest, and the peak that change. "
      "Energy: the work of the estimated external torque on the arm. Contact: a push on link k "
      "acts on joints 1..k only, so it is on the link of the most distal joint that crossed its "
      "threshold or beyond it (a push along a distal joint's axis leaves that joint quiet).";
  if (o.events.empty())
    report.paragraph("No residual crossed its threshold.");
  else
    report.table(events);
  report.heading("Thresholds");
  DocumentTable th;
  th.header = {"joint",        "threshold [N m]", "at rest [N m]",  "observer RMS",
               "observer max", "direct RMS",      "calibration RMS"};
  const Eigen::Index n = o.thresholds.values.size();
  const Eigen::VectorXd& at_rest = o.thresholds.values_at_rest;
  for (Eigen::Index j = 0; j < n; ++j)
    th.rows.push_back(
        {std::to_string(j + 1), formatNumber(o.thresholds.values[j], 4),
         at_rest.size() ? formatNumber(at_rest[j], 4) : "-", formatNumber(o.observer_rms[j], 3),
         formatNumber(o.observer_max[j], 3), o.has_direct ? formatNumber(o.direct_rms[j], 3) : "-",
         o.thresholds.calibration_rms.size() ? formatNumber(o.thresholds.calibration_rms[j], 3)
                                             : "-"});
  th.caption = "Thresholds from " + o.thresholds.source + ", set for " +
               formatNumber(o.thresholds.false_alarms_per_hour, 3) +
               " false alarms per hour of the arm: the largest of Rice's formula (the calibration "
               "residual's RMS and rate RMS), the Gumbel law of its 1 s maxima and its largest "
               "value, for the moving arm on its residual and at rest on the residual's change "
               "from its level at rest. Observer gain " +
               formatNumber(o.thresholds.gain.maxCoeff(), 4) + " 1/s.";
  report.table(th);
  if (o.thresholds.values_by_regime.size() > 0) report.table(regimesTable(o.thresholds));
  std::string warning;
  if (const auto svg = residualFigure(o))
    report.figure({"residuals",
                   "Each joint's residual (its range per plotted interval), its single moving "
                   "threshold dashed (a moving regime's own threshold is in the table above), "
                   "the events shaded.",
                   *svg});
  else
    warning = "warning: gnuplot is not available: the report has no figure\n";
  report.heading("Method");
  report.paragraph(
      "The generalized-momentum observer r = K (p - p0 - integral (tau - g - tau_f + C^T dq + r) "
      "dt) with p = M dq needs no acceleration; it follows the external joint torque through a "
      "first-order lag of time constant 1/K. The direct residual tau - tau_hat(q, dq, ddq) uses "
      "the log's accelerations. Data: " +
      data_file + ".");
  OutputSet set(dir);
  set.add("monitor.json", jsonText(withProvenance(monitorJson(o)), 2) + "\n");
  json thresholds = monitorThresholdsJson(o.thresholds);
  embedModel(thresholds, o.model, o.source);  // the arm they were set for
  set.add("thresholds.json", jsonText(withProvenance(thresholds), 2) + "\n");
  set.add("report.md", report.markdown());
  set.add("report.html", report.html());
  for (const Figure& f : report.figures()) set.add(f.name + ".svg", f.svg);
  set.publish();
  return monitorSummary(o) + warning + "wrote " + dir +
         "/monitor.json, thresholds.json, report.md, report.html\n";
}

}  // namespace dynid
