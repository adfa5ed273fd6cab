#include "reports/log_study_report.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "analysis/records/document.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"

namespace dynid {

namespace {

std::string percent(double fraction) { return formatNumber(100.0 * fraction, 3, "n/a") + " %"; }

std::string describeKey(const std::string& key) {
  if (key == "model") return "the robot's own parameters (the input model)";
  if (key == "start") return "the searches' start: the physically consistent (pc) estimate";
  return methodDescription(parseMethod(key));
}

/// The row with the smallest value of `field` among the methods (not model or start).
const LogStudyRow* best(const LogStudyOutcome& o, double LogStudyRow::*field) {
  const LogStudyRow* out = nullptr;
  for (const LogStudyRow& row : o.rows) {
    if (row.key == "model" || row.key == "start" || !std::isfinite(row.*field)) continue;
    if (out == nullptr || row.*field < out->*field) out = &row;
  }
  return out;
}

const LogStudyRow* find(const LogStudyOutcome& o, const std::string& key) {
  for (const LogStudyRow& row : o.rows)
    if (row.key == key) return &row;
  return nullptr;
}

std::optional<std::string> errorFigure(const LogStudyOutcome& o) {
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 800,520 font 'sans,11' background rgb 'white'\n"
    << "set title 'held-out data: torque fit against motion prediction'\n"
    << "set logscale xy\nset grid\nset key off\nset xlabel 'relative torque error [%]'\n"
    << "set ylabel 'GC error'\nset offsets graph 0.08, graph 0.15, graph 0.1, graph 0.1\n"
    << "$m << EOD\n";
  int points = 0;
  PlotRows rows;  // the label first: (key, torque error [%], GC error)
  for (const LogStudyRow& row : o.rows)
    if (std::isfinite(row.torque_test) && std::isfinite(row.gc_test) && row.torque_test > 0.0 &&
        row.gc_test > 0.0) {
      rows.append(row.key, {100.0 * row.torque_test, row.gc_test});
      ++points;
    }
  s << rows
    << "EOD\nplot $m using 2:3 with points pt 7 ps 1.2 lc rgb '#4477aa', "
       "$m using 2:3:1 with labels offset 1,0.7 left font 'sans,10'\n";
  if (points == 0) return std::nullopt;
  return gnuplotSvg(s);
}

}  // namespace

nlohmann::json logStudyJson(const LogStudyOutcome& o) {
  nlohmann::json rows = nlohmann::json::object(), order = nlohmann::json::array();
  for (const LogStudyRow& r : o.rows) {
    order.push_back(r.key);
    rows[r.key] = {{"torque_relative_error_train", numberOrNull(r.torque_train)},
                   {"torque_relative_error_test", numberOrNull(r.torque_test)},
                   {"gc_error_train", numberOrNull(r.gc_train)},
                   {"gc_error_test", numberOrNull(r.gc_test)},
                   {"physically_consistent", r.consistent},
                   {"evaluations", r.evaluations},
                   {"seconds", r.seconds},
                   {"note", r.note}};
  }
  return {{"schema_version", kStudyDocument.schema_version},
          {"kind", kStudyDocument.kind},
          {"robot_spec", o.robot_spec},
          {"data", {{"train", o.data_file}, {"test", o.validate_file}}},
          {"samples", {{"train", o.train_samples}, {"test", o.test_samples}}},
          {"gc",
           {{"horizon", o.horizon},
            {"segments_train", o.train_segments},
            {"segments_test", o.test_segments}}},
          {"num_base", o.num_base},
          {"num_standard", o.num_standard},
          {"order", order},
          {"methods", rows},
          {"interrupted", o.interrupted},
          {"seconds", o.seconds}};
}

std::string logStudyTable(const LogStudyOutcome& o) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-16s %12s %12s %12s %12s %10s %8s\n", "model", "tau train",
                "tau test", "GC train", "GC test", "physical", "seconds");
  out << line;
  for (const LogStudyRow& r : o.rows) {
    std::snprintf(line, sizeof(line), "%-16s %12s %12s %12s %12s %10s %8s\n", r.key.c_str(),
                  percent(r.torque_train).c_str(), percent(r.torque_test).c_str(),
                  formatNumber(r.gc_train, 3, "n/a").c_str(),
                  formatNumber(r.gc_test, 3, "n/a").c_str(), r.consistent ? "yes" : "no",
                  formatNumber(r.seconds, 3, "n/a").c_str());
    out << line;
  }
  return out.str();
}

std::vector<std::string> logStudyConclusions(const LogStudyOutcome& o) {
  std::vector<std::string> out;
  const LogStudyRow* torque = best(o, &LogStudyRow::torque_test);
  const LogStudyRow* motion = best(o, &LogStudyRow::gc_test);
  const LogStudyRow* model = find(o, "model");
  if (torque != nullptr)
    out.push_back("Best held-out torque fit: " + torque->key + ", " + percent(torque->torque_test) +
                  " (GC error " + formatNumber(torque->gc_test, 3, "n/a") + ").");
  if (motion != nullptr)
    out.push_back("Best held-out motion prediction: " + motion->key + ", GC error " +
                  formatNumber(motion->gc_test, 3, "n/a") + " (torque error " +
                  percent(motion->torque_test) + ").");
  if (torque != nullptr && motion != nullptr) {
    if (torque == motion)
      out.push_back("The same estimate is best for both: use " + torque->key +
                    " for control and for simulation.");
    else
      out.push_back(
          "The best torque fit is not the best motion predictor, as in the paper: for "
          "simulation (forward dynamics) use " +
          motion->key + ", for feed-forward torques " + torque->key + ".");
  }
  if (model != nullptr && motion != nullptr && std::isfinite(model->gc_test))
    out.push_back("The input model's held-out GC error is " +
                  formatNumber(model->gc_test, 3, "n/a") +
                  (motion->gc_test < model->gc_test
                       ? "; the best estimate lowers it " +
                             formatNumber(model->gc_test / motion->gc_test, 3, "n/a") + " times."
                       : "; no estimate predicts the motion better."));
  for (const LogStudyRow& r : o.rows)
    if (r.key != "model" && r.key != "start" && !r.consistent)
      out.push_back(r.key + " is not physically consistent: a simulator may refuse it or diverge.");
  if (o.interrupted) out.push_back("Interrupted: the table has the methods that finished.");
  return out;
}

Document logStudyDocument(const LogStudyOutcome& o) {
  Document doc("dynid study: " + o.robot_spec + " on " + o.data_file);
  doc.paragraph(
      "Every estimation method on the user's own data, measured on the training data (" +
      std::to_string(o.train_samples) + " samples of " + o.data_file + ") and on held-out data (" +
      std::to_string(o.test_samples) + " samples of " + o.validate_file + "). The torque error " +
      "is |tau - tau_hat| / |tau| over every joint and sample; the GC error, the paper's, sums " +
      "the squared state errors of " + std::to_string(o.train_segments) + " (training) and " +
      std::to_string(o.test_segments) + " (held-out) rollouts of " +
      formatNumber(o.horizon, 3, "n/a") +
      " s from the recorded states under the recorded torques. " + std::to_string(o.num_base) +
      " of the " + std::to_string(o.num_standard) + " standard parameters are identifiable. " +
      formatNumber(o.seconds, 3, "n/a") + " s in all.");
  doc.heading("Comparison");
  DocumentTable table;
  table.header = {"model",
                  "torque error, train",
                  "torque error, held out",
                  "GC train",
                  "GC held out",
                  "physically consistent",
                  "evaluations",
                  "seconds"};
  for (const LogStudyRow& r : o.rows)
    table.rows.push_back({r.key, percent(r.torque_train), percent(r.torque_test),
                          formatNumber(r.gc_train, 3, "n/a"), formatNumber(r.gc_test, 3, "n/a"),
                          r.consistent ? "yes" : "no", std::to_string(r.evaluations),
                          formatNumber(r.seconds, 3, "n/a")});
  table.caption = "Evaluations: GC evaluations for searches, iterations for refinements and pc.";
  doc.table(table);
  DocumentTable legend;
  legend.header = {"model", "what it is"};
  for (const LogStudyRow& r : o.rows)
    legend.rows.push_back({r.key, describeKey(r.key) + (r.note.empty() ? "" : "; " + r.note)});
  doc.table(legend);
  doc.heading("What to conclude");
  doc.bullets(logStudyConclusions(o));
  if (const std::optional<std::string> svg = errorFigure(o))
    doc.figure({"torque_vs_gc",
                "Each model's held-out torque error against its held-out GC "
                "error: the lower left is best at both.",
                *svg});
  return doc;
}

std::string writeLogStudy(const std::string& dir, const LogStudyOutcome& o) {
  const Document doc = logStudyDocument(o);
  std::vector<std::pair<std::string, std::string>> files = {
      {"study.json", jsonText(logStudyJson(o), 2) + "\n"},
      {"report.md", doc.markdown()},
      {"report.html", doc.html()}};
  for (const Figure& f : doc.figures()) files.emplace_back(f.name + ".svg", f.svg);
  writeReportFiles(dir, files);
  std::string out = logStudyTable(o);
  for (const std::string& sentence : logStudyConclusions(o)) out += sentence + "\n";
  out += "report: " + dir + "/report.html (and report.md, study.json)\n";
  if (doc.figures().empty()) out += "warning: gnuplot did not run: the report has no figure\n";
  return out;
}

}  // namespace dynid
