#include "reports/log_study_report.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>

#include "analysis/estimation/front.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "analysis/runs/identify.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "data/model_json.hpp"
#include "reports/log_study_figure.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"
#include "reports/prediction_report.hpp"

namespace dynid {

namespace {

std::string describeKey(const std::string& key) {
  if (key == "model") return "the robot's own parameters (the input model)";
  if (key == "start") return "the searches' start: the physically consistent (pc) estimate";
  return methodDescription(parseMethod(key));
}

const LogStudyRow* find(const LogStudyOutcome& o, const std::string& key) {
  for (const LogStudyRow& row : o.rows)
    if (row.key == key) return &row;
  return nullptr;
}

/// "held-out torque error 1.1 %, GC error 72.2".
std::string heldOutErrors(const LogStudyRow& r) {
  return "held-out torque error " + percentText(r.torque_test) + ", GC error " +
         formatNumber(r.gc_test, 3, "n/a");
}

/// A row's key, or "the front's point at w = 0.3" for the front's point `index`.
std::string estimateLabel(const LogStudyOutcome& o, const std::string& key, int index) {
  if (index < 0) return key;
  return "the front's point at w = " + formatNumber(o.front[index].weight, 3, "n/a");
}

/// The study's one recommendation once a front was swept: which estimate, and why.
std::string choiceSentence(const LogStudyOutcome& o) {
  const StudyChoice c = studyChoice(o, o.front_tolerance);
  const LogStudyRow* chosen = studyChosenRow(o, c);
  if (chosen == nullptr)
    return "none: no physically consistent estimate (front included) has finite held-out errors.";
  const std::string bound =
      "held-out torque error is at most " + formatNumber(100.0 * o.front_tolerance, 3, "n/a") +
      " % above the least of theirs (" + estimateLabel(o, c.best_torque, c.best_front_index) +
      "'s; bound " + percentText(c.torque_bound) + ")";
  const std::string what = estimateLabel(o, c.key, c.front_index) + " (" + heldOutErrors(*chosen);
  if (c.at_floor)
    return what + ", its noise floor " + formatNumber(chosen->gc_floor_test, 3, "n/a") +
           "): among the physically consistent estimates whose " + bound +
           ", the held-out GC errors are at their noise floors (what the torque noise alone "
           "causes in the rollouts): the motion cannot tell them apart, so the least held-out "
           "torque error decides.";
  return what +
         "): the least held-out GC error above its noise floor among the physically "
         "consistent estimates whose " +
         bound + ".";
}

/// front.csv: a row per point of the front, each number in the shortest text that reads back as it.
std::string frontCsv(const LogStudyOutcome& o) {
  std::string out =
      "weight,torque_relative_error_train,torque_relative_error_test,gc_error_train,gc_error_test,"
      "physically_consistent,iterations,seconds\n";
  for (const FrontRow& f : o.front) {
    const LogStudyRow& r = f.row;
    out += formatNumber(f.weight, 0) + "," + formatNumber(r.torque_train, 0, "nan") + "," +
           formatNumber(r.torque_test, 0, "nan") + "," + formatNumber(r.gc_train, 0, "nan") + "," +
           formatNumber(r.gc_test, 0, "nan") + "," + (r.consistent ? "1" : "0") + "," +
           std::to_string(r.evaluations) + "," + formatNumber(r.seconds, 0, "nan") + "\n";
  }
  return out;
}

}  // namespace

namespace {

nlohmann::json rowJson(const LogStudyRow& r) {
  return {{"torque_relative_error_train", numberOrNull(r.torque_train)},
          {"torque_relative_error_test", numberOrNull(r.torque_test)},
          {"gc_error_train", numberOrNull(r.gc_train)},
          {"gc_error_test", numberOrNull(r.gc_test)},
          {"gc_noise_floor_test", numberOrNull(r.gc_floor_test)},
          {"physically_consistent", r.consistent},
          {"evaluations", r.evaluations},
          {"seconds", r.seconds},
          {"note", r.note}};
}

/// A row's standard parameters by name (the robot's layout).
nlohmann::json standardJson(const Model& model, const Eigen::VectorXd& standard) {
  nlohmann::json out = nlohmann::json::object();
  const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
  for (Eigen::Index k = 0; k < standard.size() && k < static_cast<Eigen::Index>(names.size()); ++k)
    out[names[k]] = numberOrNull(standard[k]);
  return out;
}

/// The front's points and the choice: which estimate, by which rule, at which bound.
nlohmann::json frontJson(const LogStudyOutcome& o) {
  nlohmann::json points = nlohmann::json::array();
  for (const FrontRow& f : o.front) {
    nlohmann::json point = rowJson(f.row);
    point["weight"] = f.weight;
    point["standard"] = standardJson(o.model, f.row.standard);
    points.push_back(point);
  }
  return {{"tolerance", o.front_tolerance}, {"points", points}};
}

nlohmann::json choiceJson(const LogStudyOutcome& o) {
  const StudyChoice c = studyChoice(o, o.front_tolerance);
  return {{"key", c.key.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.key)},
          {"front_weight", c.front_index >= 0 ? nlohmann::json(o.front[c.front_index].weight)
                                              : nlohmann::json(nullptr)},
          {"best_torque",
           c.best_torque.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.best_torque)},
          {"torque_bound", c.key.empty() ? nlohmann::json(nullptr) : numberOrNull(c.torque_bound)},
          {"estimate", c.key.empty() ? nlohmann::json(nullptr) : nlohmann::json("chosen.json")},
          {"at_noise_floor", c.key.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.at_floor)},
          {"rule",
           "among the physically consistent estimates whose held-out torque error is within "
           "(1 + tolerance) of the least of theirs, the least held-out GC error above its noise "
           "floor (within 10 % of the floor counts as at it); at the floor, the least held-out "
           "torque error"}};
}

}  // namespace

nlohmann::json logStudyJson(const LogStudyOutcome& o) {
  nlohmann::json rows = nlohmann::json::object(), order = nlohmann::json::array();
  for (const LogStudyRow& r : o.rows) {
    order.push_back(r.key);
    rows[r.key] = rowJson(r);
  }
  nlohmann::json out = {{"schema_version", kStudyDocument.schema_version},
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
                        {"front", frontJson(o)},
                        {"choice", choiceJson(o)},
                        {"interrupted", o.interrupted},
                        {"seconds", o.seconds}};
  embedModel(out, o.model, o.source);  // the robot studied
  return out;
}

std::string logStudyTable(const LogStudyOutcome& o) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-16s %12s %12s %12s %12s %10s %8s\n", "model", "tau train",
                "tau test", "GC train", "GC test", "physical", "seconds");
  out << line;
  for (const LogStudyRow& r : o.rows) {
    std::snprintf(line, sizeof(line), "%-16s %12s %12s %12s %12s %10s %8s\n", r.key.c_str(),
                  percentText(r.torque_train).c_str(), percentText(r.torque_test).c_str(),
                  formatNumber(r.gc_train, 3, "n/a").c_str(),
                  formatNumber(r.gc_test, 3, "n/a").c_str(), r.consistent ? "yes" : "no",
                  formatNumber(r.seconds, 3, "n/a").c_str());
    out << line;
  }
  for (const FrontRow& f : o.front) {
    const LogStudyRow& r = f.row;
    const std::string key = "front w=" + formatNumber(f.weight, 3, "n/a");
    std::snprintf(line, sizeof(line), "%-16s %12s %12s %12s %12s %10s %8s\n", key.c_str(),
                  percentText(r.torque_train).c_str(), percentText(r.torque_test).c_str(),
                  formatNumber(r.gc_train, 3, "n/a").c_str(),
                  formatNumber(r.gc_test, 3, "n/a").c_str(), r.consistent ? "yes" : "no",
                  formatNumber(r.seconds, 3, "n/a").c_str());
    out << line;
  }
  return out.str();
}

std::vector<std::string> logStudyConclusions(const LogStudyOutcome& o) {
  std::vector<std::string> out;
  if (!o.front.empty()) out.push_back("Chosen: " + choiceSentence(o));
  const StudyVerdict v = studyVerdict(o.rows);
  const auto errors = heldOutErrors;
  const LogStudyRow* sim = find(o, v.simulation);
  const LogStudyRow* ctl = find(o, v.control);
  if (sim == nullptr) {
    out.push_back(
        "No physically consistent estimate has finite held-out errors: none is recommended.");
  } else if (v.oneForBoth()) {
    out.push_back("Use " + sim->key +
                  " for simulation and for control: among the physically consistent estimates it "
                  "predicts the held-out motion best and fits the held-out torques best (" +
                  errors(*sim) + ").");
  } else {
    out.push_back("For simulation (forward dynamics), use " + sim->key +
                  ": the best held-out motion prediction among the physically consistent "
                  "estimates (" +
                  errors(*sim) + ").");
    out.push_back("For control and monitoring (feed-forward torques), use " + ctl->key +
                  ": the best held-out torque fit among the physically consistent estimates (" +
                  errors(*ctl) + ").");
  }
  // The overall bests, when no recommendation can be: information, not advice.
  std::vector<std::pair<std::string, const char*>> bests;
  if (v.best_torque == v.best_gc)
    bests = {{v.best_torque, "fits the held-out torques and predicts the held-out motion best"}};
  else
    bests = {{v.best_torque, "fits the held-out torques best"},
             {v.best_gc, "predicts the held-out motion best"}};
  for (const auto& [key, what] : bests) {
    const LogStudyRow* r = find(o, key);
    if (r != nullptr && !r->consistent)
      out.push_back(r->key + " " + what + " (" + errors(*r) +
                    ") but is not physically consistent, so it is not recommended: a simulator "
                    "may refuse it or diverge.");
  }
  const LogStudyRow* model = find(o, "model");
  if (model != nullptr && sim != nullptr && std::isfinite(model->gc_test) && sim != model)
    out.push_back("The input model's held-out GC error is " +
                  formatNumber(model->gc_test, 3, "n/a") +
                  (sim->gc_test < model->gc_test
                       ? "; " + sim->key + " lowers it " +
                             formatNumber(model->gc_test / sim->gc_test, 3, "n/a") + " times."
                       : "; no consistent estimate predicts the motion better."));
  if (o.fit_reversals.samples > 0)
    if (const std::string friction =
            missingFrictionNote(parseDriveTerms(o.drive_terms), o.fit_reversals,
                                "the least-squares estimate's training residual");
        !friction.empty())
      out.push_back("Missing " + friction + ".");
  for (const LogStudyRow& r : o.rows)
    if (!r.moved) out.push_back(r.key + " did not move from its start: " + r.note + ".");
  if (o.interrupted) out.push_back("Interrupted: the table has the methods that finished.");
  return out;
}

namespace {
/// The recommended key and, for a front's point, its weight (the chosen estimate once a front
/// was swept, else the verdict's).
std::pair<std::string, std::optional<double>> recommended(const LogStudyOutcome& o) {
  if (o.front.empty()) {
    const StudyVerdict v = studyVerdict(o.rows);
    return {!v.simulation.empty() ? v.simulation : v.control, std::nullopt};
  }
  const StudyChoice c = studyChoice(o, o.front_tolerance);
  if (c.front_index < 0) return {c.key, std::nullopt};
  return {"combined", o.front[c.front_index].weight};
}

/// How to get the recommended estimate: the identify run that repeats it with the study's
/// settings (spelt by `spell`), or what to do for the input model or a search.
std::string nextStep(const LogStudyOutcome& o, const RepeatSpelling& spell) {
  const std::string key = recommended(o).first;
  if (key.empty()) return "see the comparison below: no physically consistent estimate finished.";
  if (key == "model")
    return "the input model itself is the recommended one: use " + o.robot_spec +
           " as it is; the details follow.";
  const std::optional<StudyRepeat> repeat = studyRepeat(o);
  if (!repeat)
    return "the recommended " + key +
           " estimate comes from a GC-error search: repeat it with dynid search and dynid "
           "refine (docs/SEARCH.md), then dynid predict; the details follow.";
  const bool urdf = !repeat->write_urdf.empty();
  const std::string command = "`" + (spell ? spell(*repeat) : repeatByFields(*repeat)) + "`";
  if (repeat->front)
    return "the chosen estimate is in chosen.json (a dynid JSON model, for payload, monitor, "
           "predict and simulate); " +
           command + " sweeps the same front and writes its estimate.json" +
           (urdf ? " and a copy of the URDF" : "") +
           (repeat->front_differs
                ? ", choosing among the front's points alone: here another point than this "
                  "study's, whose torque bound an estimate off the front set"
                : " (the same point)") +
           "; check it on another log with dynid predict; the details follow.";
  return "the recommended estimate is " + key + "'s: " + command + " writes it" +
         (urdf ? " into a copy of the URDF" : "") +
         "; check it on another log with dynid predict; the details follow.";
}

/// The verdict box: what was compared, which estimate to use for what, what is not determined.
std::vector<std::pair<std::string, std::string>> logStudyVerdict(const LogStudyOutcome& o,
                                                                 const RepeatSpelling& spell) {
  const StudyVerdict v = studyVerdict(o.rows);
  std::vector<std::pair<std::string, std::string>> lines;
  lines.emplace_back("Estimated", std::to_string(o.rows.size()) + " models of " + o.robot_spec +
                                      " (every method, and the input model) on " +
                                      std::to_string(o.train_samples) + " samples of " +
                                      o.data_file + ", judged on " +
                                      std::to_string(o.test_samples) + " held-out samples.");
  const auto row = [&](const std::string& key) { return find(o, key); };
  std::string how;
  if (v.oneForBoth()) {
    how = "use " + v.simulation +
          " for simulation and for control: " + heldOutErrors(*row(v.simulation));
  } else {
    if (const LogStudyRow* s = row(v.simulation))
      how = "for simulation " + s->key + " (" + heldOutErrors(*s) + ")";
    if (const LogStudyRow* c = row(v.control))
      how += (how.empty() ? "" : "; ") + std::string("for control and monitoring ") + c->key +
             " (" + heldOutErrors(*c) + ")";
  }
  if (!o.front.empty()) lines.emplace_back("Chosen", choiceSentence(o));
  lines.emplace_back("How well", how.empty()
                                     ? "no physically consistent estimate finished: none is "
                                       "recommended (see the comparison)"
                                     : how + ".");
  lines.emplace_back("Not determined", std::to_string(o.num_standard - o.num_base) + " of the " +
                                           std::to_string(o.num_standard) +
                                           " standard parameter directions are invisible to "
                                           "torques and to the GC error alike.");
  lines.emplace_back("Next", nextStep(o, spell));
  return lines;
}
}  // namespace

std::optional<StudyRepeat> studyRepeat(const LogStudyOutcome& o) {
  const auto [key, front_weight] = recommended(o);
  if (key != "ols" && key != "wls" && key != "pc" && key != "combined") return std::nullopt;
  StudyRepeat r;
  r.method = key;
  r.robot_spec = o.robot_spec;
  r.drive_terms = o.drive_terms;
  r.data_file = o.data_file;
  r.validate_file = o.validate_file;
  r.out = key;
  if ((key == "pc" || key == "combined") && o.prior_weight != kDefaultPriorWeight)
    r.prior_weight = o.prior_weight;
  if (key == "combined") {
    const IdentifyRequest identify;  // its defaults
    if (front_weight) {
      r.front = true;
      std::vector<double> weights;
      for (const FrontRow& f : o.front) weights.push_back(f.weight);
      if (weights != defaultFrontWeights()) r.front_weights = weights;
      if (o.front_tolerance != identify.front_tolerance) r.front_tolerance = o.front_tolerance;
      // identify's choice: among the front's points alone.
      std::vector<HeldOutErrors> errors;
      for (const FrontRow& f : o.front)
        errors.push_back({f.row.torque_test, f.row.gc_test, f.row.consistent, f.row.gc_floor_test});
      const int index = chooseByHeldOut(errors, o.front_tolerance).index;
      r.front_differs = index < 0 || o.front[index].weight != *front_weight;
    } else if (o.combined_weight != identify.combined.gc_weight) {
      r.combined_weight = o.combined_weight;
    }
    if (o.refine_seconds != identify.combined.max_seconds) r.combined_seconds = o.refine_seconds;
    if (o.refine_iterations != identify.combined.max_iterations)
      r.combined_iterations = o.refine_iterations;
    const SegmentOptions defaults = normalisedSegments();
    if (o.segments.horizon != defaults.horizon) r.horizon = o.segments.horizon;
    if (o.segments.num_segments != defaults.num_segments) r.segments = o.segments.num_segments;
    r.raw_gc = !o.segments.normalise;
  }
  if (o.robot_spec.size() > 5 && o.robot_spec.ends_with(".urdf"))
    r.write_urdf = key + "/identified.urdf";
  return r;
}

std::string repeatByFields(const StudyRepeat& r) {
  std::string out = "identify with method = " + r.method + ", robot_spec = " + r.robot_spec +
                    ", drive_terms = " + r.drive_terms + ", data_file = " + r.data_file +
                    ", validate_file = " + r.validate_file + ", out = " + r.out;
  const auto number = [&](const char* field, const std::optional<double>& x) {
    if (x) out += std::string(", ") + field + " = " + formatNumber(*x);
  };
  number("prior_weight", r.prior_weight);
  number("combined_weight", r.combined_weight);
  number("combined_seconds", r.combined_seconds);
  number("horizon", r.horizon);
  if (r.combined_iterations)
    out += ", combined_iterations = " + std::to_string(*r.combined_iterations);
  if (r.segments) out += ", segments = " + std::to_string(*r.segments);
  if (r.raw_gc) out += ", raw_gc";
  if (r.front) {
    out += ", front_weights = ";
    const std::vector<double> weights =
        r.front_weights.empty() ? defaultFrontWeights() : r.front_weights;
    for (std::size_t k = 0; k < weights.size(); ++k) {
      if (k > 0) out += ",";
      out += formatNumber(weights[k]);
    }
  }
  number("front_tolerance", r.front_tolerance);
  if (!r.write_urdf.empty()) out += ", write_urdf = " + r.write_urdf;
  return out;
}

Document logStudyDocument(const LogStudyOutcome& o, const RepeatSpelling& spell) {
  Document doc("dynid study: " + o.robot_spec + " on " + o.data_file);
  doc.verdict(logStudyVerdict(o, spell));
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
  // The report opens with the picture: every model's torque fit against its motion prediction,
  // and the front between them.
  if (const std::optional<std::string> svg = studyFigure(o))
    doc.figure({"torque_vs_gc",
                "Each model's held-out torque error against its held-out GC "
                "error: the lower left is best at both (when the physically consistent "
                "estimates cluster far from the rest, a second panel zooms on them)." +
                    std::string(o.front.empty() ? ""
                                                : " The line is the front (the combined estimator "
                                                  "from w small to large); the ring marks the "
                                                  "chosen estimate."),
                *svg});
  doc.heading("Comparison");
  DocumentTable table;
  table.header = {"model",       "torque error, train", "torque error, held out", "GC train",
                  "GC held out", "its noise floor",     "physically consistent",  "evaluations",
                  "seconds"};
  for (const LogStudyRow& r : o.rows)
    table.rows.push_back({r.key, percentText(r.torque_train), percentText(r.torque_test),
                          formatNumber(r.gc_train, 3, "n/a"), formatNumber(r.gc_test, 3, "n/a"),
                          formatNumber(r.gc_floor_test, 3, "n/a"), r.consistent ? "yes" : "no",
                          std::to_string(r.evaluations), formatNumber(r.seconds, 3, "n/a")});
  table.caption =
      "Evaluations: GC evaluations for searches, iterations for refinements and pc. Noise floor: "
      "the held-out GC error the torque noise alone causes with that model (the noise level of its "
      "torque residual, rolled out); a GC error near its floor says nothing of the model, and a "
      "model that damps the noise more sits lower.";
  doc.table(table);
  DocumentTable legend;
  legend.header = {"model", "what it is"};
  for (const LogStudyRow& r : o.rows)
    legend.rows.push_back({r.key, describeKey(r.key) + (r.note.empty() ? "" : "; " + r.note)});
  doc.table(legend);
  if (!o.front.empty()) {
    doc.heading("The front");
    doc.paragraph(
        "The combined estimator at each GC weight w, each point started from the last, every "
        "point with pc's normalisers: from the best physically consistent torque fit towards the "
        "best motion prediction. Every point is physically consistent by construction.");
    DocumentTable front;
    front.header = {"w",           "torque error, train", "torque error, held out", "GC train",
                    "GC held out", "its noise floor",     "physically consistent",  "iterations",
                    "seconds"};
    for (const FrontRow& f : o.front)
      front.rows.push_back({formatNumber(f.weight, 3, "n/a"), percentText(f.row.torque_train),
                            percentText(f.row.torque_test), formatNumber(f.row.gc_train, 3, "n/a"),
                            formatNumber(f.row.gc_test, 3, "n/a"),
                            formatNumber(f.row.gc_floor_test, 3, "n/a"),
                            f.row.consistent ? "yes" : "no", std::to_string(f.row.evaluations),
                            formatNumber(f.row.seconds, 3, "n/a")});
    doc.table(front);
  }
  doc.heading("What to conclude");
  doc.bullets(logStudyConclusions(o));
  return doc;
}

std::string writeLogStudy(const std::string& dir, const LogStudyOutcome& o,
                          const RepeatSpelling& spell) {
  const Document doc = logStudyDocument(o, spell);
  std::vector<std::pair<std::string, std::string>> files = {
      {"study.json", jsonText(withProvenance(logStudyJson(o)), 2) + "\n"},
      {"report.md", doc.markdown()},
      {"report.html", doc.html()}};
  if (!o.front.empty()) files.emplace_back("front.csv", frontCsv(o));
  const StudyChoice choice = studyChoice(o, o.front_tolerance);
  const LogStudyRow* chosen = o.front.empty() ? nullptr : studyChosenRow(o, choice);
  const bool write_chosen =
      chosen != nullptr && chosen->standard.size() == o.model.standardParameters().size();
  if (write_chosen) {
    Model model = o.model;
    model.setStandardParameters(chosen->standard);
    files.emplace_back("chosen.json", modelToJson(model));
  }
  for (const Figure& f : doc.figures()) files.emplace_back(f.name + ".svg", f.svg);
  writeReportFiles(dir, files);
  std::string out = logStudyTable(o);
  for (const std::string& sentence : logStudyConclusions(o)) out += sentence + "\n";
  out += "report: " + dir + "/report.html (and report.md, study.json" +
         (o.front.empty() ? "" : ", front.csv") + ")\n";
  if (write_chosen)
    out += "the chosen estimate: " + dir +
           "/chosen.json (a dynid JSON model: the arm of payload and monitor, the robot of predict "
           "and simulate)\n";
  if (doc.figures().empty()) out += "warning: gnuplot did not run: the report has no figure\n";
  return out;
}

}  // namespace dynid
