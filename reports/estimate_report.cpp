// The identification report of `dynid identify` (report.md, report.html and their figures), and
// the files of an identification written together.
#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"
#include "reports/identification_report.hpp"
#include "reports/output.hpp"
#include "reports/prediction_report.hpp"

namespace dynid {

namespace {

/// "a, b and c" (at most `limit` names, then "and N more").
std::string nameList(const std::vector<std::string>& names, std::size_t limit = 40) {
  std::string out;
  const std::size_t shown = std::min(names.size(), limit);
  for (std::size_t k = 0; k < shown; ++k) {
    if (k > 0) out += k + 1 == shown && shown == names.size() ? " and " : ", ";
    out += names[k];
  }
  if (shown < names.size()) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

/// The training fit's figures and the held-out one's, drawn at once (one gnuplot each), then
/// placed in order; from summaries, no training sample is left to draw.
void fitFigures(Document& doc, const IdentifyOutcome& o, std::vector<std::string>& missing) {
  const Prediction* validate = o.validate_fit ? &*o.validate_fit : nullptr;
  const bool samples = o.fit.time.size() > 0;
  if (!samples)
    doc.paragraph("Identified from least-squares summaries of " +
                  std::to_string(o.summary_sources.size()) +
                  " logs (dynid summarize): they hold the fit's rows, not its samples, so the "
                  "training fit has no figures; estimate.json's data.sources lists the logs.");
  std::vector<std::function<std::optional<std::string>()>> draws;
  if (samples)
    draws = {[&] { return torqueFigure(o.fit, "training data: measured and predicted torques"); },
             [&] { return residualFigure(o.fit, validate); },
             [&] { return residualHistogram(o.fit); }};
  if (validate)
    draws.push_back(
        [&] { return torqueFigure(*validate, "held-out data: measured and predicted torques"); });
  const std::vector<std::optional<std::string>> svgs = drawConcurrently(draws);
  const auto add = [&](const std::string& name, const std::optional<std::string>& svg,
                       const std::string& caption) {
    if (svg)
      doc.figure({name, caption, *svg});
    else
      missing.push_back(name + ".svg");
  };
  const std::size_t held = samples ? 3 : 0;  // the held-out figure's place among the draws
  if (samples)
    add("torques_train", svgs[0],
        "Measured (blue) against predicted (red) joint torques on the training data.");
  if (validate)
    add("torques_validate", svgs[held],
        "Measured against predicted joint torques on the held-out data: what the estimate "
        "predicts on motion it was not fitted to.");
  if (!samples) return;
  add("residuals", svgs[1],
      "Torque residuals against time. Structure that repeats with the motion (spikes at velocity "
      "reversals, drift with temperature) is unmodelled dynamics, not noise.");
  add("residual_histogram", svgs[2],
      "Histogram of each joint's training residuals (every sample up to 8192, evenly spaced "
      "samples beyond) against the normal density of the same RMS. "
      "A shifted peak is a bias (an offset the drive terms lack), two peaks unmodelled Coulomb "
      "friction.");
}

void torqueFitSection(Document& doc, const Model& model, const IdentifyOutcome& o,
                      std::vector<std::string>& missing) {
  doc.heading("Torque fit");
  const Validation& t = o.fit.validation;
  const Validation* v = o.validate_fit ? &o.validate_fit->validation : nullptr;
  doc.paragraph(
      "Relative torque error |tau - tau_hat| / |tau| over every joint and sample (the "
      "literature's measure): " +
      percentText(t.relative_error) + " on the " + std::to_string(t.num_samples) +
      " training samples of " + o.data_file +
      (v ? ", " + percentText(v->relative_error) + " on the " + std::to_string(v->num_samples) +
               " held-out samples of " + o.validate_file
         : std::string(", no held-out data (give --validate to measure it)")) +
      ".");
  DocumentTable table;
  table.header = {"joint", "measured RMS [N m]", "residual RMS [N m]", "relative error"};
  if (v)
    table.header.insert(table.header.end(),
                        {"held-out residual RMS [N m]", "held-out relative error"});
  const Eigen::Index n = t.torque_rms.size();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double measured = o.fit.measured_rms[j];
    std::vector<std::string> row = {std::to_string(j + 1), formatNumber(measured, 3, "n/a"),
                                    formatNumber(t.torque_rms[j], 3, "n/a"),
                                    percentText(t.normalised_rms[j])};
    if (v)
      row.insert(row.end(),
                 {formatNumber(v->torque_rms[j], 3, "n/a"), percentText(v->normalised_rms[j])});
    table.rows.push_back(row);
  }
  table.caption = "Relative error per joint: residual RMS over measured RMS.";
  doc.table(table);
  if (const ReversalResidual& r = o.reversals; r.samples > 0) {
    DocumentTable reversals;
    reversals.header = {"joint", "band: |dq| under [rad/s]", "share of the samples",
                        "share of the squared residual"};
    for (Eigen::Index j = 0; j < r.speed.size(); ++j) {
      const bool flagged = std::find(r.flagged.begin(), r.flagged.end(), j) != r.flagged.end();
      reversals.rows.push_back({std::to_string(j + 1) + (flagged ? " (flagged)" : ""),
                                formatNumber(r.speed[j], 3), percentText(r.sample_share[j]),
                                percentText(r.residual_share[j])});
    }
    reversals.caption =
        "Where the training residual lies in velocity: the samples within a tenth of each "
        "joint's RMS speed of zero velocity (reversals, rest), measured on " +
        std::to_string(r.samples) + " evenly spaced samples.";
    doc.table(reversals);
    if (const std::string note = reversalNote(model.driveTerms(), o.reversals, filteringClause(o));
        !note.empty())
      doc.paragraph("Note: " + note + ".");
  }
  doc.paragraph("Uncertainty: " + covarianceLine(o.result.covariance) +
                ". The standard deviations, the held-out torque bands of dynid predict and dynid "
                "audit's tests all use this covariance.");
  if (const std::string line = restVelocityLine(o.rest); !line.empty())
    doc.paragraph("Friction at rest: " + line +
                  ". Within a joint's rest velocity sign(dq) is noise: Coulomb, asymmetry and "
                  "Stribeck friction are static there, any torque within their limits, predicted "
                  "as zero (estimate.json's rest_velocity says how each velocity was measured).");
  if (const std::string line = fitRowsLine(o); !line.empty())
    doc.paragraph("Rows of the fit: " + line +
                  ". A filtered torque is matched by filtering the friction columns the same way, "
                  "so that a reversal's step, which the filter spreads, is not read as a "
                  "missing friction term (estimate.json's fit_rows).");
  fitFigures(doc, o, missing);
}

void preparationSection(Document& doc, const PreparationFound& found) {
  doc.heading("Preprocessing (dynid prepare)");
  std::vector<std::string> items;
  if (!found.record) {
    doc.bullets({"(prepare.json lacks fields this version reads; see the file itself)"});
    return;
  }
  const PrepareRecord& p = *found.record;
  const auto number = [](double x) { return formatNumber(x, 3, "n/a"); };
  const auto ms = [](double x) {
    return std::isfinite(x) ? formatNumber(1e3 * x, 4) + " ms" : std::string("n/a");
  };
  items.push_back(std::to_string(p.raw_samples) + " raw samples; time step median " +
                  ms(p.median_step) + ", from " + ms(p.min_step) + " to " + ms(p.max_step) + "; " +
                  std::to_string(p.repeated_stamps_dropped) + " repeated stamps dropped.");
  items.push_back("Gaps longer than " + ms(p.max_gap) + ": " + std::to_string(p.gaps) +
                  "; runs between them: " + std::to_string(p.runs) + " kept, " +
                  std::to_string(p.dropped_runs) +
                  " dropped (shorter than the filter's transient).");
  items.push_back(
      "Resampled to " + formatNumber(p.resampled_rate, 4) + " Hz; filter: " + p.filter_kind +
      (p.cutoff_hz > 0.0 ? ", order " + std::to_string(p.filter_order) + ", cutoff " +
                               formatNumber(p.cutoff_hz, 4) + " Hz, applied to " + p.applied_to
                         : std::string()) +
      ".");
  if (p.cutoff_choice) items.push_back("Cutoff: " + *p.cutoff_choice + ".");
  items.push_back("dq: " + p.dq + "; ddq: " + p.ddq + "; " + number(p.trimmed_each_end) +
                  " s trimmed at each run's ends; every " + std::to_string(p.decimate) +
                  " sample kept.");
  std::string noise;
  for (double x : p.tau_noise_rms) noise += (noise.empty() ? "" : ", ") + number(x);
  items.push_back("Torque noise removed by the filter (RMS per joint) [N m]: " + noise + ".");
  doc.bullets(items);
}

void identifiabilitySection(const Model& model, Document& doc, const IdentifyOutcome& o) {
  const BaseParameters& base = o.base;
  const BaseEstimate& e = o.result.estimate;
  doc.heading("What the data identify");
  doc.paragraph(std::to_string(base.numBase()) + " of the " + std::to_string(base.numStandard()) +
                " standard parameters of " + model.name + " (drive terms " +
                driveTermsText(model.driveTerms()) +
                ") are identifiable, as the base parameters below. Condition number of the "
                "training base regressor: " +
                formatNumber(e.condition_number_unscaled, 3, "n/a") +
                " as it is (physical units, what most papers report), " +
                formatNumber(e.condition_number, 3, "n/a") +
                " with unit columns (independent of units).");
  DocumentTable table;
  table.header = {"#",  "base parameter", "combination", "estimate",
                  "%σ", "excitation",     "model value"};
  // The model's base values are projections: round-off of the largest shows as 1e-16 noise.
  const double floor = 1e-12 * o.model_beta.cwiseAbs().maxCoeff();
  for (int j = 0; j < base.numBase(); ++j)
    table.rows.push_back(
        {std::to_string(j + 1), base.baseName(j), base.expression(j), formatNumber(e.beta[j], 4),
         formatNumber(e.relative_std_dev_percent[j], 3, "n/a"),
         j < e.independence.size() ? formatNumber(e.independence[j], 3, "n/a") : "n/a",
         formatNumber(std::abs(o.model_beta[j]) <= floor ? 0.0 : o.model_beta[j], 4)});
  table.caption =
      "%σ: the estimate's standard deviation relative to its value. Excitation: the share of the "
      "parameter's torque signature (its regressor column) that no other base parameter's "
      "explains, sqrt(1 - R²), from 1 (on its own) to 0 (a combination of the others).";
  doc.table(table);
}

/// The combined estimator's two criteria against pc's, train and held out.
void combinedSection(Document& doc, const IdentifyOutcome& o) {
  if (!o.combined) return;
  const CombinedSummary& c = *o.combined;
  const CombinedResult& d = c.detail;
  doc.heading("Torques and motion together (combined)");
  doc.paragraph(
      "The combined estimator minimises pc's objective (the torque residuals and the divergence "
      "from the prior) plus the GC residuals of " +
      std::to_string(c.train_segments) +
      " training rollouts, each criterion normalised by its value at the pc estimate, from "
      "there; every iterate is physically consistent. " +
      std::to_string(d.iterations) + " Jacobians, " + formatNumber(d.seconds, 3, "n/a") +
      " s: " + d.termination + (d.moved ? "." : "; no step was taken (the estimate is pc's)."));
  const Validation* v = o.validate_fit ? &o.validate_fit->validation : nullptr;
  DocumentTable table;
  table.header = {"estimate", "torque error, train", "held out", "GC error, train", "held out"};
  table.rows.push_back({"pc (the start)", percentText(c.torque_train_pc),
                        percentText(c.torque_test_pc), formatNumber(c.gc_train_pc, 4, "n/a"),
                        formatNumber(c.gc_test_pc, 4, "n/a")});
  table.rows.push_back({"combined", percentText(o.fit.validation.relative_error),
                        v ? percentText(v->relative_error) : "n/a",
                        formatNumber(c.gc_train, 4, "n/a"), formatNumber(c.gc_test, 4, "n/a")});
  table.caption = "GC error: the sum over the rollouts of the squared state errors at their end" +
                  std::string(c.test_segments > 0
                                  ? " (" + std::to_string(c.test_segments) + " held-out rollouts)"
                                  : "") +
                  ".";
  doc.table(table);
}

/// With `front_weights`: the front's points on the held-out data and the one chosen.
void frontSection(Document& doc, const IdentifyOutcome& o) {
  if (!o.front) return;
  const IdentifyFront& f = *o.front;
  const IdentifyFrontPoint& chosen = f.points[f.choice.index];
  doc.heading("The front, and the estimate chosen from it");
  doc.paragraph(
      "The combined estimator at " + std::to_string(f.points.size()) +
      " GC weights w, each point started from the last with pc's normalisers, every point "
      "physically consistent. The estimate is the point at w = " +
      formatNumber(chosen.weight, 3, "n/a") +
      ": among the points whose held-out torque error is at most " +
      formatNumber(100.0 * f.tolerance, 3, "n/a") + " % above the least of theirs (w = " +
      formatNumber(f.points[f.choice.best_torque].weight, 3, "n/a") + "'s; bound " +
      percentText(f.choice.torque_bound) + "), " +
      (f.choice.at_floor
           ? "whose held-out GC errors are all at their noise floors (what the torque noise alone "
             "causes in the rollouts: the motion cannot tell them apart), the least held-out "
             "torque error."
           : "the least held-out GC error above its noise floor."));
  DocumentTable table;
  table.header = {"w",        "torque error, train", "held out",   "GC error, train",
                  "held out", "its noise floor",     "iterations", "seconds"};
  for (const IdentifyFrontPoint& p : f.points)
    table.rows.push_back({formatNumber(p.weight, 3, "n/a") + (&p == &chosen ? " (chosen)" : ""),
                          percentText(p.torque_train), percentText(p.test.torque),
                          formatNumber(p.gc_train, 4, "n/a"), formatNumber(p.test.gc, 4, "n/a"),
                          formatNumber(p.test.gc_floor, 4, "n/a"), std::to_string(p.iterations),
                          formatNumber(p.seconds, 3, "n/a")});
  doc.table(table);
}

void consistencySection(Document& doc, const Model& model, const IdentifyOutcome& o) {
  doc.heading("Physical consistency");
  if (o.result.pc)
    doc.paragraph("The physically consistent solver (pc) stopped after " +
                  std::to_string(o.result.pc->iterations) +
                  " iterations: " + o.result.pc->termination + ". Prior weight " +
                  formatNumber(o.prior_weight, 3, "n/a") + ".");
  else
    doc.paragraph("The " + std::string(methodName(o.method)) +
                  " estimate fixes the base parameters only; the standard parameters checked here "
                  "take the directions the data cannot see from the model. An inconsistent link "
                  "means this lift is unphysical, not that no physical lift exists: --method pc "
                  "finds one.");
  DocumentTable table;
  table.header = {"link", "verdict"};
  for (int i = 0; i < model.numJoints(); ++i) {
    std::string verdict;
    for (const ConsistencyViolation& v : o.violations)
      if (v.link == i)
        verdict += (verdict.empty() ? "violates: " : "; ") + v.condition + " (" + v.detail + ")";
    table.rows.push_back({model.link_names[i], verdict.empty() ? "consistent" : verdict});
  }
  doc.table(table);
}

void unknownsSection(Document& doc, const IdentifyOutcome& o) {
  const BaseParameters& base = o.base;
  const BaseEstimate& e = o.result.estimate;
  doc.heading("What the data cannot determine");
  std::vector<std::string> never, regrouped, uncertain, collinear;
  for (int k : base.zero_columns) never.push_back(base.standard_names[k]);
  for (int k : base.dependent)
    if (std::find(base.zero_columns.begin(), base.zero_columns.end(), k) == base.zero_columns.end())
      regrouped.push_back(base.standard_names[k]);
  for (int j = 0; j < base.numBase(); ++j) {
    if (!(e.relative_std_dev_percent[j] <= 10.0))
      uncertain.push_back(base.baseName(j) + " (" +
                          formatNumber(e.relative_std_dev_percent[j], 3, "n/a") + " %)");
    if (j < e.independence.size() && e.independence[j] < 0.1)
      collinear.push_back(base.baseName(j) + " (" + formatNumber(e.independence[j], 3, "n/a") +
                          ")");
  }
  std::vector<std::string> items;
  items.push_back(never.empty() ? "Every standard parameter acts on the torques."
                                : std::to_string(never.size()) +
                                      " standard parameters never act on the torques, whatever "
                                      "the motion: " +
                                      nameList(never) + ".");
  if (!regrouped.empty())
    items.push_back(std::to_string(regrouped.size()) +
                    " are identifiable only in the combinations of the table above, never "
                    "alone: " +
                    nameList(regrouped) + ".");
  items.push_back(uncertain.empty() ? "Every base parameter has %σ at most 10 %."
                                    : std::to_string(uncertain.size()) +
                                          " base parameters have %σ above 10 % (the usual "
                                          "threshold for a well-identified parameter; often "
                                          "small values whose torque is near the noise): " +
                                          nameList(uncertain) + ".");
  if (!collinear.empty())
    items.push_back(std::to_string(collinear.size()) +
                    " base parameters are excited mostly in combination with others (excitation "
                    "below 0.1): " +
                    nameList(collinear) +
                    ". A motion that moves their joints differently would separate them.");
  items.push_back(std::to_string(base.numStandard() - base.numBase()) +
                  " directions of the standard parameters are invisible to torque data; the "
                  "standard estimate takes them from the " +
                  (o.result.pc ? "prior" : "model") + ".");
  doc.bullets(items);
}

/// Where the torques came from, and what that means for the estimate: every inertial parameter
/// scales with the torque, so with currents it is only as right as the constants.
std::string torqueSource(const IdentifyOutcome& o) {
  if (o.preparation.present && o.preparation.record &&
      !o.preparation.record->torque_constants.empty()) {
    const PrepareRecord& p = *o.preparation.record;
    std::string constants;
    for (std::size_t j = 0; j < p.torque_constants.size(); ++j)
      constants += (j == 0 ? "" : ", ") + formatNumber(p.torque_constants[j], 4) + " x " +
                   formatNumber(j < p.gear_ratios.size() ? p.gear_ratios[j] : 1.0, 4);
    return "motor current x torque constant [N m/A] x gear ratio, per joint: " + constants +
           " (dynid prepare). Every inertial and friction parameter scales with these constants: "
           "a constant 5 % off makes that joint's share 5 % off.";
  }
  if (o.preparation.present)
    return "the log's torque columns as recorded (dynid prepare converted no currents): a joint "
           "torque sensor or the controller's own torque estimate.";
  return "the dataset's tau columns as given. If they were computed from motor currents, every "
         "parameter is only as right as the torque constants used.";
}

/// What would determine the poorly determined base parameters (%σ above 10 %), by cause: with the
/// same motion and noise σ falls as 1/sqrt(samples), so %σ up to 20 % comes within 10 % with 4
/// times the samples; a value within 2σ of zero is not significantly different from zero (its
/// torque is below the noise: its %σ says little, and no motion makes it larger); one nearly a
/// combination of the others (independence below 0.1) needs a motion that separates them.
std::string uncertainAdvice(const IdentifyOutcome& o) {
  const BaseEstimate& e = o.result.estimate;
  int longer = 0, zero = 0, entangled = 0, other = 0;
  for (Eigen::Index j = 0; j < e.relative_std_dev_percent.size(); ++j) {
    const double percent = e.relative_std_dev_percent[j];
    if (percent <= 10.0) continue;
    if (percent <= 20.0)
      ++longer;
    else if (j < e.beta.size() && j < e.std_dev.size() && std::abs(e.beta[j]) < 2.0 * e.std_dev[j])
      ++zero;
    else if (j < e.independence.size() && e.independence[j] < 0.1)
      ++entangled;
    else
      ++other;
  }
  std::vector<std::string> parts;
  if (longer > 0)
    parts.push_back(std::to_string(longer) +
                    " would come within 10 % with 4 times the samples of this motion (σ falls as "
                    "1/√samples)");
  if (zero > 0)
    parts.push_back(std::to_string(zero) +
                    " are not significantly different from zero (|estimate| < 2σ: their torque is "
                    "below the noise, which is what the data say about them)");
  if (entangled + other > 0)
    parts.push_back(std::to_string(entangled + other) +
                    (entangled > 0
                         ? " (" + std::to_string(entangled) + " nearly combinations of others)"
                         : std::string()) +
                    " need more excitation: a motion designed by dynid excite, or a longer log");
  if (parts.empty()) return "";
  std::string out = "of the " + std::to_string(longer + zero + entangled + other) +
                    " poorly determined base parameters, ";
  for (std::size_t k = 0; k < parts.size(); ++k)
    out += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
  return out;
}

/// The verdict box: what was estimated, how well, what is not determined, what to do next.
std::vector<std::pair<std::string, std::string>> identificationVerdict(const Model& model,
                                                                       const IdentifyOutcome& o) {
  const BaseParameters& base = o.base;
  const BaseEstimate& e = o.result.estimate;
  std::vector<std::string> uncertain;
  for (int j = 0; j < base.numBase(); ++j)
    if (!(e.relative_std_dev_percent[j] <= 10.0)) uncertain.push_back(base.baseName(j));
  std::vector<std::pair<std::string, std::string>> lines;
  lines.emplace_back("Estimated", std::to_string(base.numBase()) + " base parameters of " +
                                      model.name + " by " + methodDescription(o.method) + " from " +
                                      std::to_string(e.num_samples) + " samples of " + o.data_file +
                                      ".");
  std::string how =
      "relative torque error " + percentText(e.relative_error) + " on the training data";
  how += o.validation ? ", " + percentText(o.validation->relative_error) + " held out (" +
                            o.validate_file + ")"
                      : "; not checked on held-out data";
  how += "; " + std::to_string(base.numBase() - static_cast<int>(uncertain.size())) + " of " +
         std::to_string(base.numBase()) + " base parameters within 10 % (%σ).";
  if (o.result.pc || !o.violations.empty())
    how += o.violations.empty() ? " Every link is physically consistent."
                                : " " + std::to_string(o.violations.size()) +
                                      " physical-consistency violations in the standard estimate.";
  lines.emplace_back("How well", how);
  std::string unknown = std::to_string(base.numStandard() - base.numBase()) +
                        " directions of the " + std::to_string(base.numStandard()) +
                        " standard parameters are invisible to torque data (taken from the " +
                        (o.result.pc ? "prior" : "model") + ")";
  if (!uncertain.empty()) {
    std::vector<std::string> shown(uncertain.begin(),
                                   uncertain.begin() + std::min<std::size_t>(uncertain.size(), 6));
    unknown += "; " + std::to_string(uncertain.size()) +
               " base parameters are poorly determined (%σ above 10 %): " + nameList(shown) +
               (uncertain.size() > shown.size()
                    ? " and " + std::to_string(uncertain.size() - shown.size()) + " more"
                    : "");
  }
  lines.emplace_back("Not determined", unknown + ".");
  lines.emplace_back("Torque source", torqueSource(o));
  std::vector<std::string> next;
  if (const std::string warning = solverWarning(o); !warning.empty()) next.push_back(warning);
  if (!o.validation)
    next.push_back(
        "check it on other data: dynid predict --estimate estimate.json --data "
        "test.csv");
  if (!o.result.pc && !o.violations.empty())
    next.push_back("--method pc for an estimate every link of which is a physical body");
  if (const std::string advice = uncertainAdvice(o); !advice.empty()) next.push_back(advice);
  if (const std::string note = reversalNote(model.driveTerms(), o.reversals, filteringClause(o));
      !note.empty())
    next.push_back(note);
  if (next.empty())
    next.push_back("use it: --write-urdf (for a URDF robot), dynid predict, dynid monitor");
  std::string joined;
  for (const std::string& n : next) joined += (joined.empty() ? "" : "; ") + n;
  lines.emplace_back("Next", joined + ".");
  return lines;
}

}  // namespace

Document identificationDocument(const Model& model, const IdentifyOutcome& o,
                                std::vector<std::string>* missing_figures) {
  Document doc("dynid identify: " + model.name + " (" + methodName(o.method) + ")");
  doc.verdict(identificationVerdict(model, o));
  doc.paragraph(std::string(methodDescription(o.method)) + ": " + std::to_string(o.base.numBase()) +
                " base parameters from " + std::to_string(o.result.estimate.num_samples) +
                " samples of " + o.data_file +
                (o.robot_spec.empty() ? "" : "; robot " + o.robot_spec) + ".");
  if (const std::string warning = solverWarning(o); !warning.empty())
    doc.paragraph("Warning: " + warning);
  std::vector<std::string> missing;
  torqueFitSection(doc, model, o, missing);
  combinedSection(doc, o);
  frontSection(doc, o);
  if (o.preparation.present) preparationSection(doc, o.preparation);
  identifiabilitySection(model, doc, o);
  consistencySection(doc, model, o);
  unknownsSection(doc, o);
  if (missing_figures) *missing_figures = missing;
  return doc;
}

std::string writeIdentification(const std::string& dir, const Model& model,
                                const IdentifyOutcome& outcome) {
  std::vector<std::string> missing;
  const Document doc = identificationDocument(model, outcome, &missing);
  std::vector<std::pair<std::string, std::string>> files = {
      {"estimate.json", jsonText(withProvenance(estimateJson(model, outcome)), 2) + "\n"},
      {"report.md", doc.markdown()},
      {"report.html", doc.html()}};
  for (const Figure& f : doc.figures()) files.emplace_back(f.name + ".svg", f.svg);
  writeReportFiles(dir, files);
  std::string out = estimateSummary(model, outcome, dir);
  if (!missing.empty())
    out += "warning: gnuplot did not run: the report has no figures (" + nameList(missing) + ")\n";
  return out;
}

}  // namespace dynid
