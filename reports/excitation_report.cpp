#include "reports/excitation_report.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "reports/identification_report.hpp"
#include "reports/model_report.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"

namespace dynid {

namespace {

nlohmann::json vectorJson(const Eigen::VectorXd& v) { return numbersOrNull(v); }

nlohmann::json rowsJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) rows.push_back(numbersOrNull(m.row(i).transpose()));
  return rows;
}

nlohmann::json scoreJson(const MotionScore& s) {
  return {{"samples", s.samples},
          {"condition_unit", numberOrNull(s.condition_unit)},
          {"condition", numberOrNull(s.condition)},
          {"log_det", numberOrNull(s.log_det)},
          {"relative_sd_rms", numberOrNull(s.relative_rms)},
          {"std_dev", vectorJson(s.std_dev)},
          {"relative_std_percent", vectorJson(s.relative_std)}};
}

nlohmann::json checkJson(const LimitCheck& c) {
  return {{"rate", c.rate},
          {"q_low", vectorJson(c.q_low)},
          {"q_high", vectorJson(c.q_high)},
          {"dq_peak", vectorJson(c.dq_peak)},
          {"ddq_peak", vectorJson(c.ddq_peak)},
          {"tau_peak", vectorJson(c.tau_peak)},
          {"lowest_origin", numberOrNull(c.lowest_origin)},
          {"nearest_base", numberOrNull(c.nearest_base)},
          {"violations", c.violations}};
}

std::vector<std::string> baseNames(const BaseParameters& base) {
  std::vector<std::string> names;
  for (int j = 0; j < base.numBase(); ++j) names.push_back(base.baseName(j));
  return names;
}

std::string percent(double x) { return formatNumber(x, x < 10.0 ? 2 : 3, "n/a") + " %"; }

/// Each joint's q, dq and ddq over the period as fractions of its limits (1: at the limit).
std::optional<std::string> trajectoryFigure(const Model& model, const ExciteOutcome& o) {
  const Trajectory t = sampleFourier(o.design, model, std::max(50.0, 400.0 / o.design.period));
  const ExcitationLimits& l = o.limits;
  PlotScript s;
  s << "set terminal svg size 900,720 font 'sans,11' background rgb 'white'\n"
    << "set multiplot layout 3,1 title 'the design against its limits (1 = at the limit)'\n"
    << "set grid\nset key outside right\nset yrange [-1.1:1.1]\n"
    << "set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 lc rgb '#aa3377'\n"
    << "set arrow 2 from graph 0, first -1 to graph 1, first -1 nohead lw 2 lc rgb '#aa3377'\n";
  const int n = model.numJoints();
  const char* kinds[] = {"position (q - middle) / half range", "velocity dq / dq_max",
                         "acceleration ddq / ddq_max"};
  for (int kind = 0; kind < 3; ++kind) {
    PlotRows rows;
    std::vector<double> row(n + 1);
    for (int k = 0; k < t.numSamples(); ++k) {
      row[0] = t.time[k];
      for (int j = 0; j < n; ++j) {
        const double half = 0.5 * (l.q_max[j] - l.q_min[j]),
                     middle = 0.5 * (l.q_max[j] + l.q_min[j]);
        row[j + 1] = kind == 0   ? (t.q(j, k) - middle) / half
                     : kind == 1 ? t.dq(j, k) / l.dq_max[j]
                                 : t.ddq(j, k) / l.ddq_max[j];
      }
      rows.append(row);
    }
    s << "$d" << kind << " << EOD\n"
      << rows << "EOD\nset ylabel " << gnuplotString(kinds[kind]) << "\n";
    if (kind == 2) s << "set xlabel 't [s]'\n";
    s << "plot ";
    for (int j = 0; j < n; ++j) {
      if (j > 0) s << ", ";
      s << "$d" << kind << " using 1:" << j + 2 << " with lines lw 1.5 title "
        << gnuplotString(model.joint_names[j]);
    }
    s << "\n";
  }
  s << "unset multiplot\n";
  return gnuplotSvg(s);
}

/// Expected relative standard deviation of every base parameter, designed vs the sinusoid.
std::optional<std::string> deviationFigure(const ExciteOutcome& o) {
  const int b = o.base.numBase();
  PlotScript s;
  s << "set terminal svg size 900,420 font 'sans,11' background rgb 'white'\nset title "
    << gnuplotString("expected relative standard deviation of each base parameter at " +
                     formatNumber(o.torque_noise) + " N m torque noise")
    << "\nset logscale y\nset grid ytics\nset key top left\nset ylabel '%'\n"
    << "set style data histogram\nset style histogram clustered gap 1\nset style fill solid 0.8\n"
    << "set xtics rotate by -60 font 'sans,8' noenhanced\n$d << EOD\n";
  PlotRows rows;
  for (int j = 0; j < b; ++j) {
    const double designed = o.score.relative_std[j], sinusoid = o.baseline.relative_std[j];
    rows.append(o.base.baseName(j), {std::isfinite(designed) ? designed : 1e6,
                                     std::isfinite(sinusoid) ? sinusoid : 1e6});
  }
  s << rows
    << "EOD\nplot $d using 2:xtic(1) title 'designed' lc rgb '#4477aa', '' using 3 title "
       "'default sinusoid' lc rgb '#ee6677'\n";
  return gnuplotSvg(s);
}

}  // namespace

nlohmann::json excitationJson(const Model& model, const ExcitationSettings& settings,
                              const ExciteOutcome& o) {
  const ExcitationLimits& l = o.limits;
  nlohmann::json out = {
          {"schema_version", kExcitationDocument.schema_version},
          {"kind", kExcitationDocument.kind},
          {"robot", settings.robot},
          {"joints", model.joint_names},
          {"design",
           {{"period", o.design.period},
            {"harmonics", o.design.harmonics()},
            {"offset", vectorJson(o.design.offset)},
            {"a", rowsJson(o.design.a)},
            {"b", rowsJson(o.design.b)},
            {"form",
             "q_j(t) = offset_j + sum_k a_jk/(w k) sin(w k t) - b_jk/(w k) cos(w k t), "
             "w = 2 pi / period"}}},
          {"criterion", excitationCriterionName(o.criterion)},
          {"payload_link", o.payload_link ? nlohmann::json(model.link_names[*o.payload_link])
                                          : nlohmann::json(nullptr)},
          {"limits",
           {{"q_min", vectorJson(l.q_min)},
            {"q_max", vectorJson(l.q_max)},
            {"dq_max", vectorJson(l.dq_max)},
            {"ddq_max", vectorJson(l.ddq_max)},
            {"tau_max", vectorJson(l.tau_max)},
            {"torque_margin", l.torque_margin},
            {"floor", l.floor ? nlohmann::json(*l.floor) : nlohmann::json(nullptr)},
            {"base_radius", l.base_radius},
            {"notes", l.notes}}},
          {"base_parameters", baseNames(o.base)},
          {"torque_noise", o.torque_noise},
          {"designed", scoreJson(o.score)},
          {"default_sinusoid", scoreJson(o.baseline)},
          {"gc_condition_unit",
           {{"segments", o.gc_segments},
            {"horizon", o.gc_horizon},
            {"designed", numberOrNull(o.gc)},
            {"default_sinusoid", numberOrNull(o.baseline_gc)},
            {"designed_first_order", numberOrNull(o.gc_first_order)},
            {"default_sinusoid_first_order", numberOrNull(o.baseline_gc_first_order)}}},
          {"stand", settings.stand ? standJson(*settings.stand) : nlohmann::json(nullptr)},
          {"check", checkJson(o.check)},
          {"default_sinusoid_check", checkJson(o.baseline_check)},
          {"optimiser",
           {{"method", "COBYLA (NLopt), multistart"},
            {"starts", settings.starts},
            {"evaluations_per_start", settings.evaluations},
            {"grid_rate", o.grid_rate},
            {"best_start", o.best_start},
            {"start_criteria",
             [&] {
               nlohmann::json a = nlohmann::json::array();
               for (const ExciteStart& s : o.starts) a.push_back(numberOrNull(s.objective));
               return a;
             }()},
            {"shrink", o.shrink},
            {"termination", o.termination},
            {"evaluations", o.evaluations},
            {"seconds", o.seconds},
            {"seed", o.seed}}}};
  // The robot designed for (with its drive terms): the design is usable without its file.
  embedModel(out, model,
             settings.source.spec.empty() ? ModelSource{settings.robot, "", ""} : settings.source);
  return out;
}

std::string excitationCsv(const Model& model, const FourierSeries& design, double rate) {
  const Trajectory t = sampleFourier(design, model, rate);
  const int n = model.numJoints();
  std::ostringstream out;
  out << "t";
  for (const char* kind : {"q", "dq", "ddq"})
    for (int j = 0; j < n; ++j) out << ',' << kind << j + 1;
  out << '\n';
  for (int k = 0; k < t.numSamples(); ++k) {
    out << formatNumber(t.time[k]);
    for (const Eigen::MatrixXd* m : {&t.q, &t.dq, &t.ddq})
      for (int j = 0; j < n; ++j) out << ',' << formatNumber((*m)(j, k));
    out << '\n';
  }
  return out.str();
}

namespace {

/// The criteria of the design and of the default sinusoid, side by side.
DocumentTable criteriaTable(const ExciteOutcome& o) {
  DocumentTable criteria;
  criteria.header = {"criterion", "designed", "default sinusoid"};
  criteria.rows = {
      {"condition number, unit columns", formatNumber(o.score.condition_unit, 4),
       formatNumber(o.baseline.condition_unit, 4)},
      {"condition number, SI units", formatNumber(o.score.condition, 4),
       formatNumber(o.baseline.condition, 4)},
      {"log det(W1^T W1 / rows)", formatNumber(o.score.log_det, 4),
       formatNumber(o.baseline.log_det, 4)},
      {"GC Jacobian condition number, unit columns",
       formatNumber(o.gc, 4, "not computed (interrupted)"),
       formatNumber(o.baseline_gc, 4, "not computed (interrupted)")},
      {"first-order GC (M^-1 W1), unit columns", formatNumber(o.gc_first_order, 4),
       formatNumber(o.baseline_gc_first_order, 4)},
      {"RMS expected relative std. dev. (" + formatNumber(o.torque_noise) + " N m noise)",
       formatNumber(o.score.relative_rms, 4), formatNumber(o.baseline.relative_rms, 4)},
      {"largest expected std. dev. (" + formatNumber(o.torque_noise) + " N m noise)",
       formatNumber(o.score.std_dev.maxCoeff(), 4),
       formatNumber(o.baseline.std_dev.maxCoeff(), 4)}};
  criteria.caption = "W1 is the base regressor (" + std::to_string(o.base.numBase()) +
                     " base parameters) over the samples; lower condition numbers and higher "
                     "log det are better. The GC Jacobian is that of the paper's prediction "
                     "error over its segments, with respect to the base parameters.";
  return criteria;
}

/// Each joint's limits and what the design uses of them.
DocumentTable limitsTable(const Model& model, const ExciteOutcome& o) {
  DocumentTable limits;
  limits.header = {"joint",
                   "q range",
                   "q used",
                   "|dq| peak / limit",
                   "|ddq| peak / limit",
                   "|tau| peak / limit"};
  for (int j = 0; j < model.numJoints(); ++j) {
    const ExcitationLimits& l = o.limits;
    const LimitCheck& c = o.check;
    limits.rows.push_back(
        {model.joint_names[j], formatNumber(l.q_min[j], 4) + " .. " + formatNumber(l.q_max[j], 4),
         formatNumber(c.q_low[j], 4) + " .. " + formatNumber(c.q_high[j], 4),
         formatNumber(c.dq_peak[j], 4) + " / " + formatNumber(l.dq_max[j], 4),
         formatNumber(c.ddq_peak[j], 4) + " / " + formatNumber(l.ddq_max[j], 4),
         formatNumber(c.tau_peak[j], 4) + " / " +
             (std::isfinite(l.tau_max[j]) ? formatNumber(l.torque_margin * l.tau_max[j], 4)
                                          : std::string("none"))});
  }
  limits.caption = "Units: rad, rad/s, rad/s^2, N m (m, m/s, m/s^2, N for prismatic joints).";
  return limits;
}

/// The report's verdict box: the design, how it compares with the default sinusoid, the base
/// parameters it still leaves poorly determined, its limits, what to do next.
std::vector<std::pair<std::string, std::string>> verdictBox(const ExciteOutcome& o) {
  std::vector<std::string> poor;  // expected relative std. dev. above 10 %
  for (int j = 0; j < o.base.numBase(); ++j)
    if (!(o.score.relative_std[j] <= 0.1)) poor.push_back(o.base.baseName(j));
  std::string poor_text;
  for (std::size_t i = 0; i < poor.size() && i < 5; ++i) poor_text += (i ? ", " : "") + poor[i];
  if (poor.size() > 5) poor_text += " and " + std::to_string(poor.size() - 5) + " more";
  return {
      {"Designed", std::to_string(o.design.harmonics()) + " harmonics per joint over " +
                       formatNumber(o.design.period) + " s for the " +
                       excitationCriterionName(o.criterion) + " criterion" +
                       (o.termination == "interrupted" ? " (interrupted: the best so far)" : "")},
      {"How well",
       "condition number (unit columns) " + formatNumber(o.score.condition_unit, 4) +
           " against the default sinusoid's " + formatNumber(o.baseline.condition_unit, 4) +
           "; RMS expected relative std. dev. " + formatNumber(o.score.relative_rms, 3) +
           " against " + formatNumber(o.baseline.relative_rms, 3) + " (" +
           formatNumber(o.torque_noise) + " N m torque noise)"},
      {"Not determined",
       poor.empty()
           ? "none: every base parameter's expected std. dev. is within 10 %"
           : std::to_string(poor.size()) + " of " + std::to_string(o.base.numBase()) +
                 " base parameters above 10 % expected std. dev. (table below): " + poor_text},
      {"Limits", o.check.violations.empty() ? "every position, velocity, acceleration and "
                                              "torque limit holds at " +
                                                  formatNumber(o.check_rate) + " Hz"
                                            : "broken: " + o.check.violations.front()},
      {"Next", o.payload_link ? "run it with the payload, then dynid payload"
                              : "run excitation.json on the robot (or dynid simulate "
                                "--trajectory), then dynid prepare and dynid identify"}};
}

}  // namespace

Document excitationDocument(const Model& model, const ExcitationSettings& settings,
                            const ExciteOutcome& o, std::vector<std::string>* missing_figures) {
  Document doc("dynid excite: " + model.name);
  doc.verdict(verdictBox(o));
  if (o.payload_link)
    doc.paragraph("A payload motion: the design determines the 10 parameters of a payload on " +
                  model.link_names[*o.payload_link] +
                  " (the arm known), for `dynid payload`; the criteria below are of those 10 "
                  "parameters.");
  doc.paragraph("A periodic Fourier series of " + std::to_string(o.design.harmonics()) +
                " harmonics per joint over " + formatNumber(o.design.period) +
                " s, at rest at both ends, optimised for the " +
                excitationCriterionName(o.criterion) + " criterion (" +
                std::to_string(settings.starts) + " COBYLA starts, seed " + std::to_string(o.seed) +
                ", " + std::to_string(o.evaluations) + " evaluations, " +
                formatNumber(o.seconds, 4) + " s; stopped by " + o.termination +
                "). It is compared with `dynid simulate`'s default sinusoid over the same " +
                "duration. Both are scored at " + formatNumber(o.check_rate) + " Hz.");
  if (!o.limits.notes.empty()) {
    doc.paragraph("Limits the model does not give (defaults used):");
    doc.bullets(o.limits.notes);
  }
  doc.heading("Criteria");
  doc.table(criteriaTable(o));
  if (!o.baseline_check.violations.empty())
    doc.paragraph("The default sinusoid itself breaks these limits: " +
                  o.baseline_check.violations.front() + ".");
  if (settings.stand) addStandSection(doc, *settings.stand);

  // Both figures drawn at once (one gnuplot each).
  const std::vector<std::optional<std::string>> svgs = drawConcurrently(
      {[&] { return trajectoryFigure(model, o); }, [&] { return deviationFigure(o); }});
  std::vector<std::string> missing;
  if (const auto& svg = svgs[0])
    doc.figure({"trajectory",
                "Each joint's position, velocity and acceleration as a fraction "
                "of its limit; the design stays inside +-1 (checked at " +
                    formatNumber(o.check_rate) + " Hz).",
                *svg});
  else
    missing.push_back("trajectory");

  doc.heading("Limits");
  doc.table(limitsTable(model, o));

  doc.heading("Base parameters");
  DocumentTable params;
  params.header = {"base parameter", "designed: std. dev.", "%", "default sinusoid: std. dev.",
                   "%"};
  for (int j = 0; j < o.base.numBase(); ++j)
    params.rows.push_back({o.base.expression(j), formatNumber(o.score.std_dev[j], 4),
                           percent(o.score.relative_std[j]), formatNumber(o.baseline.std_dev[j], 4),
                           percent(o.baseline.relative_std[j])});
  params.caption =
      "Expected standard deviation of each base parameter by ordinary least squares "
      "with " +
      formatNumber(o.torque_noise) +
      " N m of independent torque noise on every joint, sampled at " + formatNumber(o.check_rate) +
      " Hz over one period; % is relative to the model's own value.";
  doc.table(params);
  if (const auto& svg = svgs[1])
    doc.figure({"deviations",
                "Expected relative standard deviation of each base parameter "
                "(log scale): designed against the default sinusoid.",
                *svg});
  else
    missing.push_back("deviations");
  if (missing_figures) *missing_figures = missing;
  return doc;
}

std::string writeExcitation(const std::string& dir, const Model& model,
                            const ExcitationSettings& settings, const ExciteOutcome& o) {
  std::vector<std::string> missing;
  const Document doc = excitationDocument(model, settings, o, &missing);
  std::vector<std::pair<std::string, std::string>> files = {
      {"excitation.json", jsonText(withProvenance(excitationJson(model, settings, o)), 2) + "\n"},
      {"excitation.csv", excitationCsv(model, o.design, settings.csv_rate)},
      {"report.md", doc.markdown()},
      {"report.html", doc.html()}};
  for (const Figure& f : doc.figures()) files.emplace_back(f.name + ".svg", f.svg);
  writeReportFiles(dir, files);
  std::ostringstream out;
  out << "designed " << o.design.period << " s of motion (" << o.design.harmonics()
      << " harmonics) for " << model.name << ", criterion " << excitationCriterionName(o.criterion)
      << " (" << o.evaluations << " evaluations, " << formatNumber(o.seconds, 4) << " s)\n"
      << "  condition number (unit columns): " << formatNumber(o.score.condition_unit, 4)
      << ", default sinusoid " << formatNumber(o.baseline.condition_unit, 4) << "\n"
      << "  condition number (SI units):     " << formatNumber(o.score.condition, 4)
      << ", default sinusoid " << formatNumber(o.baseline.condition, 4) << "\n"
      << "  log det per row:                 " << formatNumber(o.score.log_det, 4)
      << ", default sinusoid " << formatNumber(o.baseline.log_det, 4) << "\n"
      << "  GC Jacobian condition number:    "
      << formatNumber(o.gc, 4, "not computed (interrupted)") << ", default sinusoid "
      << formatNumber(o.baseline_gc, 4, "not computed (interrupted)") << "\n"
      << "  RMS expected relative std. dev.: " << formatNumber(o.score.relative_rms, 4)
      << ", default sinusoid " << formatNumber(o.baseline.relative_rms, 4) << "\n"
      << "  every limit holds at " << formatNumber(o.check_rate) << " Hz"
      << (o.shrink < 1.0 ? " (coefficients shrunk by " + formatNumber(o.shrink, 4) + ")" : "")
      << "\nwrote " << dir << "/excitation.json, excitation.csv (" << settings.csv_rate
      << " Hz), report.md, report.html\n";
  if (settings.stand) out << standSummary(*settings.stand);
  for (const std::string& note : o.limits.notes) out << "note: " << note << "\n";
  if (!missing.empty()) out << "warning: gnuplot did not run: the report has no figures\n";
  return out.str();
}

}  // namespace dynid
