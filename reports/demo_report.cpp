#include "reports/demo_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "analysis/studies/comparison.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "reports/document.hpp"
#include "reports/output.hpp"

namespace dynid {

namespace {

using nlohmann::json;

/// Three significant digits, as every table prints them.
std::string g3(double x) { return formatNumber(x, 3, "n/a"); }

const char* describe(const std::string& key) { return methodDescription(parseMethod(key)); }

const MethodMetrics* find(const DemoResult& result, Method method) {
  for (const MethodMetrics& m : result.methods)
    if (m.key == methodName(method)) return &m;
  return nullptr;
}

struct Column {
  const char* header;
  std::string (*format)(const MethodMetrics&);
};

const Column kColumns[] = {
    {"GC initial", [](const MethodMetrics& m) { return g3(m.gc_error_initial); }},
    {"GC train", [](const MethodMetrics& m) { return g3(m.gc_error_train); }},
    {"GC test", [](const MethodMetrics& m) { return g3(m.gc_error_test); }},
    {"torque RMS test [N m]", [](const MethodMetrics& m) { return g3(m.torque_rms_test); }},
    {"param error", [](const MethodMetrics& m) { return g3(m.param_error); }},
    {"base param error", [](const MethodMetrics& m) { return g3(m.base_param_error); }},
    {"evaluations", [](const MethodMetrics& m) { return std::to_string(m.evaluations); }},
    {"seconds", [](const MethodMetrics& m) { return g3(m.seconds); }},
};

/// What the table shows, in sentences computed from it.
std::vector<std::string> conclusions(const DemoResult& result) {
  std::vector<std::string> out;
  if (const MethodMetrics* ols = find(result, Method::kOls))
    out.push_back("Least squares on the torques recovers the " +
                  std::to_string(result.identifiability.num_base) +
                  " base parameters to a relative error of " + g3(ols->base_param_error) + " in " +
                  g3(ols->seconds) + " s; its 7-parameter error, " + g3(ols->param_error) +
                  ", is that of the initial guess's unidentifiable parameters, which the data "
                  "cannot correct.");
  for (Method method : searchMethods())
    if (const MethodMetrics* m = find(result, method))
      out.push_back(std::string(methodName(method)) + " cuts the training GC error " +
                    g3(m->gc_error_initial / m->gc_error_train) + "x (" + g3(m->gc_error_initial) +
                    " to " + g3(m->gc_error_train) + ") in " + std::to_string(m->evaluations) +
                    " evaluations, with a base-parameter error of " + g3(m->base_param_error) +
                    " and a 7-parameter error of " + g3(m->param_error) + ".");
  if (!result.near_truth.gc_errors.empty())
    out.push_back("Among " + std::to_string(result.near_truth.gc_errors.size()) +
                  " random configurations within " + g3(100.0 * result.near_truth.range) +
                  " % of the truth, " + g3(result.near_truth.percentile) +
                  " % predict the held-out path as well as the " + result.near_truth.estimate +
                  " estimate or better (held-out GC error " + g3(result.near_truth.estimate_gc) +
                  "), although its parameters are much further from the truth.");
  for (Method method : {Method::kNloRefined, Method::kGaRefined, Method::kHybridRefined})
    if (const MethodMetrics* m = find(result, method))
      out.push_back(std::string(methodName(method)) + ": refinement takes the GC error to " +
                    g3(m->gc_error_train) + " and the base-parameter error to " +
                    g3(m->base_param_error) + ", while the 7-parameter error stays at " +
                    g3(m->param_error) +
                    ": a lower prediction error does not give lower parameter errors, because "
                    "the GC error depends on the base parameters only (the paper's finding).");
  return out;
}

/// The verdict box: what was estimated, how well, what is not determined, what next.
std::vector<std::pair<std::string, std::string>> demoVerdict(const DemoResult& result) {
  const DemoIdentifiability& id = result.identifiability;
  std::vector<std::pair<std::string, std::string>> lines;
  lines.emplace_back("Estimated", "the " + std::to_string(id.num_base) + " base parameters of " +
                                      result.settings.robot + " (of " +
                                      std::to_string(id.num_standard) + " standard ones), " +
                                      std::to_string(result.methods.size()) +
                                      " ways, on noise-free simulated data from a " +
                                      g3(100.0 * result.settings.perturb) + " %-perturbed guess.");
  // The best base-parameter error of each family: least squares, the searches, the refinements.
  const auto best = [&](std::initializer_list<Method> methods) -> const MethodMetrics* {
    const MethodMetrics* out = nullptr;
    for (Method method : methods)
      if (const MethodMetrics* m = find(result, method))
        if (out == nullptr || m->base_param_error < out->base_param_error) out = m;
    return out;
  };
  std::string how;
  const auto add = [&](const char* what, const MethodMetrics* m) {
    if (m == nullptr) return;
    how += (how.empty() ? "" : "; ") + std::string(what) + " " + m->key +
           ": base-parameter error " + g3(m->base_param_error) + ", 7-parameter error " +
           g3(m->param_error);
  };
  add("least squares", best({Method::kOls, Method::kWls, Method::kPc}));
  add("best search", best({Method::kNlo, Method::kGa, Method::kHybrid}));
  add("best refinement", best({Method::kNloRefined, Method::kGaRefined, Method::kHybridRefined}));
  lines.emplace_back("How well", how.empty() ? "no method finished (interrupted)" : how + ".");
  const NullSpaces& ns = result.null_spaces;
  lines.emplace_back("Not determined",
                     std::to_string(ns.regressor_null) + " of the " + std::to_string(ns.standard) +
                         " standard parameter directions are invisible to the torques, and the "
                         "GC error is blind to the same ones: no method can find the paper's 7 "
                         "parameters of every link, only the base parameters.");
  lines.emplace_back("Next",
                     "the same comparison on your own log: dynid study --robot R --data "
                     "train.csv --validate test.csv (docs/SEARCH.md); the details follow.");
  return lines;
}

std::string verdictMarkdown(const std::vector<std::pair<std::string, std::string>>& lines) {
  std::string out = "> **Verdict**\n>\n";
  for (const auto& [label, text] : lines) out += "> - **" + label + ":** " + text + "\n";
  return out + "\n";
}

std::string verdictHtml(const std::vector<std::pair<std::string, std::string>>& lines) {
  std::string out = "<section class=\"verdict\" id=\"verdict\">\n<h2>Verdict</h2>\n<dl>\n";
  for (const auto& [label, text] : lines)
    out += "<dt>" + escapeXml(label) + "</dt><dd>" + escapeXml(text) + "</dd>\n";
  return out + "</dl>\n</section>\n";
}

/// What the null spaces say, in sentences computed from them.
std::vector<std::string> nullSpaceSentences(const DemoResult& result) {
  const NullSpaces& ns = result.null_spaces;
  std::vector<std::string> out;
  if (ns.standard == 0) return out;
  std::string line =
      "The torques cannot determine " + std::to_string(ns.regressor_null) + " of the " +
      std::to_string(ns.standard) +
      " standard parameter directions (the regressor's null space). The GC residuals' "
      "Jacobian at the truth (unit columns) has " +
      std::to_string(ns.gc_near_null) + " singular values at or below " + g3(ns.tolerance) +
      " of its largest";
  if (!ns.principal_angles_deg.empty())
    line +=
        "; the principal angles between that near-null space and the regressor's null space "
        "range from " +
        g3(ns.principal_angles_deg.front()) + " to " + g3(ns.principal_angles_deg.back()) +
        " degrees";
  line += ".";
  out.push_back(line);
  if (ns.gc_near_null == ns.regressor_null && !ns.principal_angles_deg.empty() &&
      ns.principal_angles_deg.back() < 1.0)
    out.push_back(
        "So the GC error is blind to exactly the parameter combinations the torques are blind "
        "to: a search on the GC error can at best find the base parameters, never the "
        "7 paper parameters of every link.");
  return out;
}

}  // namespace

std::string demoSummaryJson(const DemoResult& result) {
  json methods = json::object();
  json order = json::array();
  for (const MethodMetrics& m : result.methods) {
    order.push_back(m.key);
    methods[m.key] = metricsJson(m);
  }
  const StudySettings& s = result.settings;
  const DemoIdentifiability& id = result.identifiability;
  json base = json::array();
  for (std::size_t j = 0; j < id.base_names.size(); ++j)
    base.push_back({{"name", id.base_names[j]}, {"expression", id.base_expressions[j]}});
  json searches = json::array();
  for (const DemoSearchTrace& t : result.searches) {
    json history = json::array();
    for (const HistoryEntry& h : t.history)
      history.push_back({{"stage", h.stage},
                         {"iteration", h.iteration},
                         {"best_gc", numberOrNull(h.best_gc)},
                         {"best_parameter_error", numberOrNull(h.best_parameter_error)},
                         {"min_parameter_error", numberOrNull(h.min_parameter_error)},
                         {"evaluations", h.evaluations}});
    for (std::size_t i = 0; i < history.size() && i < t.base_errors.size(); ++i)
      history[i]["best_base_parameter_error"] = numberOrNull(t.base_errors[i]);
    searches.push_back({{"method", t.method},
                        {"candidates", t.candidates},
                        {"pearson_log", numberOrNull(t.pearson_log)},
                        {"spearman", numberOrNull(t.spearman)},
                        {"history", history}});
  }
  const json summary = {{"schema_version", kDemoDocument.schema_version},
                        {"kind", kDemoDocument.kind},
                        {"methods", methods},
                        {"order", order},
                        {"settings",
                         {{"robot", s.robot},
                          {"train_seconds", s.train_seconds},
                          {"test_seconds", s.test_seconds},
                          {"segments", s.segments},
                          {"horizon", s.horizon},
                          {"perturb", s.perturb},
                          {"search_seconds", s.search_seconds},
                          {"refine_iterations", s.refine_iterations},
                          {"seed", s.seed},
                          {"threads", s.threads},
                          {"quick", result.quick}}},
                        {"identifiability",
                         {{"num_standard", id.num_standard},
                          {"num_base", id.num_base},
                          {"base_parameters", base},
                          {"unidentifiable", id.unidentifiable},
                          {"ols_relative_std_dev_percent", id.ols_relative_std_dev},
                          {"condition_number", numberOrNull(id.condition_number)}}},
                        {"searches", searches},
                        {"null_spaces",
                         {{"standard", result.null_spaces.standard},
                          {"regressor_null", result.null_spaces.regressor_null},
                          {"gc_near_null", result.null_spaces.gc_near_null},
                          {"tolerance", result.null_spaces.tolerance},
                          {"gc_singular_values", result.null_spaces.gc_singular_values},
                          {"principal_angles_deg", result.null_spaces.principal_angles_deg}}},
                        {"initial_guess",
                         {{"gc_error_train", numberOrNull(result.initial_gc_train)},
                          {"gc_error_test", numberOrNull(result.initial_gc_test)}}},
                        {"near_truth",
                         {{"range", result.near_truth.range},
                          {"samples", result.near_truth.gc_errors.size()},
                          {"gc_errors_test", result.near_truth.gc_errors},
                          {"estimate", result.near_truth.estimate},
                          {"estimate_gc_test", numberOrNull(result.near_truth.estimate_gc)},
                          {"percentile", numberOrNull(result.near_truth.percentile)}}},
                        {"interrupted", result.interrupted},
                        {"seconds", result.seconds}};
  return jsonText(withProvenance(summary), 1) + "\n";
}

std::string demoTable(const DemoResult& result) {
  // Each column as wide as its header or its widest value (at least 12): headers are not cut.
  std::size_t key_width = 12;
  for (const MethodMetrics& m : result.methods) key_width = std::max(key_width, m.key.size());
  std::vector<std::size_t> widths;
  for (const Column& c : kColumns) {
    std::size_t width = std::max<std::size_t>(12, std::strlen(c.header));
    for (const MethodMetrics& m : result.methods) width = std::max(width, c.format(m).size());
    widths.push_back(width);
  }
  const auto padded = [](const std::string& text, std::size_t width, bool left) {
    const std::string pad(width > text.size() ? width - text.size() : 0, ' ');
    return left ? text + pad : pad + text;
  };
  std::ostringstream out;
  out << padded("method", key_width, true);
  for (std::size_t c = 0; c < widths.size(); ++c)
    out << ' ' << padded(kColumns[c].header, widths[c], false);
  out << "\n";
  for (const MethodMetrics& m : result.methods) {
    out << padded(m.key, key_width, true);
    for (std::size_t c = 0; c < widths.size(); ++c)
      out << ' ' << padded(kColumns[c].format(m), widths[c], false);
    out << "\n";
  }
  return out.str();
}

std::string demoMarkdown(const DemoResult& result, const std::vector<Figure>& figures) {
  const StudySettings& s = result.settings;
  const DemoIdentifiability& id = result.identifiability;
  std::ostringstream out;
  out << "# dynid demo: " << s.robot << "\n\n";
  if (result.interrupted) out << "**Interrupted**: the table has the stages that finished.\n\n";
  out << verdictMarkdown(demoVerdict(result));
  out << "Noise-free simulated data: " << s.train_seconds << " s of training data (the default "
      << "sinusoidal controller) and " << s.test_seconds
      << " s held out on another control path, sampled at 1 kHz. The initial guess perturbs "
         "every parameter by up to "
      << 100.0 * s.perturb << " % (seed " << s.seed << "). GC error: " << s.segments
      << " segments of " << s.horizon << " s. Searches: " << s.search_seconds
      << " s each; refinement: at most " << s.refine_iterations << " iterations per stage. "
      << s.threads << " threads; " << g3(result.seconds) << " s in all.\n\n";
  out << "## Identifiability\n\n"
      << id.num_base << " of the " << id.num_standard
      << " standard parameters are identifiable as base parameters; the condition number of the "
         "training base regressor (unit columns) is "
      << g3(id.condition_number) << ".\n\n";
  if (!id.unidentifiable.empty()) {
    out << "Parameters that never affect the torques:";
    for (const std::string& name : id.unidentifiable) out << " " << name;
    out << ".\n\n";
  }
  out << "<details><summary>The " << id.base_names.size()
      << " base parameters (click to show)</summary>\n\n";
  out << "| base parameter | combination of standard parameters | %σ (OLS) |\n|---|---|---|\n";
  for (std::size_t j = 0; j < id.base_names.size(); ++j)
    out << "| " << id.base_names[j] << " | " << id.base_expressions[j] << " | "
        << (j < id.ols_relative_std_dev.size() ? g3(id.ols_relative_std_dev[j]) : "n/a") << " |\n";
  out << "\n%σ: the OLS estimate's standard deviation relative to its value, in %.\n\n</details>\n";
  for (const std::string& line : nullSpaceSentences(result)) out << "\n" << line << "\n";
  out << "\n## Comparison\n\n| method |";
  for (const Column& c : kColumns) out << " " << c.header << " |";
  out << "\n|---|";
  for (std::size_t c = 0; c < std::size(kColumns); ++c) out << "---|";
  out << "\n";
  for (const MethodMetrics& m : result.methods) {
    out << "| " << m.key << " |";
    for (const Column& c : kColumns) out << " " << c.format(m) << " |";
    out << "\n";
  }
  out << "\nGC errors are the paper's sum of squared state-prediction errors; the parameter error "
         "is the paper's eq. (1) over the searched parameters (m, c, principal inertias per "
         "link); the base-parameter error is the RMS of the base parameters' relative errors; "
         "evaluations are GC evaluations for searches, Levenberg-Marquardt iterations for "
         "refinement and pc.\n\n";
  out << "| method | what it is |\n|---|---|\n";
  for (const MethodMetrics& m : result.methods)
    out << "| " << m.key << " | " << describe(m.key) << " |\n";
  out << "\n## What to conclude\n\n";
  for (const std::string& sentence : conclusions(result)) out << "- " << sentence << "\n";
  if (!figures.empty()) {
    out << "\n## Figures\n";
    for (std::size_t f = 0; f < figures.size(); ++f)
      out << "\n" << markdownFigure(figures[f], static_cast<int>(f) + 1);
  }
  return out.str();
}

std::string demoHtml(const DemoResult& result, const std::vector<Figure>& figures) {
  const StudySettings& s = result.settings;
  const DemoIdentifiability& id = result.identifiability;
  std::ostringstream out;
  out << htmlHead("dynid demo: " + s.robot);
  if (result.interrupted)
    out << "<p><strong>Interrupted</strong>: the table has the stages that finished.</p>\n";
  out << verdictHtml(demoVerdict(result));
  out << "<p>Noise-free simulated data: " << s.train_seconds << " s training, " << s.test_seconds
      << " s held out; initial guess perturbed by up to " << 100.0 * s.perturb << " % (seed "
      << s.seed << "); " << s.segments << " GC segments of " << s.horizon << " s; searches "
      << s.search_seconds << " s each; " << g3(result.seconds) << " s in all.</p>\n";
  out << "<h2>Identifiability</h2>\n<p>" << id.num_base << " of " << id.num_standard
      << " standard parameters are identifiable as base parameters; condition number "
      << g3(id.condition_number) << ".</p>\n";
  out << "<details><summary>The " << id.base_names.size()
      << " base parameters (click to show)</summary>\n";
  out << "<table id=\"base\"><tr><th>base parameter</th><th>combination</th><th>%&sigma; "
         "(OLS)</th></tr>\n";
  for (std::size_t j = 0; j < id.base_names.size(); ++j)
    out << "<tr><td>" << escapeXml(id.base_names[j]) << "</td><td>"
        << escapeXml(id.base_expressions[j]) << "</td><td>"
        << (j < id.ols_relative_std_dev.size() ? g3(id.ols_relative_std_dev[j]) : "n/a")
        << "</td></tr>\n";
  out << "<caption>%&sigma;: the OLS estimate's standard deviation relative to its value.</caption>"
         "</table>\n</details>\n";
  for (const std::string& line : nullSpaceSentences(result))
    out << "<p>" << escapeXml(line) << "</p>\n";
  out << "\n<h2>Comparison</h2>\n<table id=\"comparison\">\n<tr><th>method</th>";
  for (const Column& c : kColumns) out << "<th>" << escapeXml(c.header) << "</th>";
  out << "</tr>\n";
  for (const MethodMetrics& m : result.methods) {
    out << "<tr><td>" << escapeXml(m.key) << "</td>";
    for (const Column& c : kColumns) out << "<td>" << escapeXml(c.format(m)) << "</td>";
    out << "</tr>\n";
  }
  out << "<caption>Every estimate measured against the same truth, data and coordinates.</caption>"
         "\n</table>\n<h2>What to conclude</h2>\n<ul>\n";
  for (const std::string& sentence : conclusions(result))
    out << "<li>" << escapeXml(sentence) << "</li>\n";
  out << "</ul>\n";
  if (!figures.empty()) out << "<h2>Figures</h2>\n";
  for (std::size_t f = 0; f < figures.size(); ++f)
    out << htmlFigure(figures[f], static_cast<int>(f) + 1);
  out << "</body>\n</html>\n";
  return out.str();
}

void writeDemoReport(const std::string& dir, const DemoResult& result,
                     const std::vector<Figure>& figures) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const Figure& figure : figures) files.emplace_back(figure.name + ".svg", figure.svg);
  files.emplace_back("summary.json", demoSummaryJson(result));
  files.emplace_back("report.md", demoMarkdown(result, figures));
  files.emplace_back("report.html", demoHtml(result, figures));
  writeReportFiles(dir, files);
}

}  // namespace dynid
