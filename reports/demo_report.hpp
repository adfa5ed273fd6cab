// The demo's outputs: summary.json (the comparison table and the settings), a Markdown report and
// a self-contained HTML report (no network access needed to view it), and the console table.
#pragma once

#include <string>

#include "analysis/studies/demo.hpp"
#include "reports/plots.hpp"

namespace dynid {

/// summary.json: schema_version 1, kind "dynid.demo", `methods` keyed by method (ols, wls, pc,
/// nlo, ga, hybrid, nlo_refined, ga_refined, hybrid_refined), each with gc_error_initial,
/// gc_error_train, gc_error_test, torque_rms_test, param_error, base_param_error, evaluations,
/// seconds; plus `order`, `settings`, `identifiability`, `interrupted` and `seconds`. Non-finite
/// numbers are null.
std::string demoSummaryJson(const DemoResult& result);
/// The comparison table as fixed-width text (what `dynid demo` prints).
std::string demoTable(const DemoResult& result);
/// The report in Markdown: settings, identifiability, the comparison table, what to conclude, and
/// the figures as `NAME.svg` files beside it (the caller writes them).
std::string demoMarkdown(const DemoResult& result, const std::vector<Figure>& figures = {});
/// The same report as one HTML file with inline CSS and inline SVG figures: no external resources.
std::string demoHtml(const DemoResult& result, const std::vector<Figure>& figures = {});
/// Writes the figures (NAME.svg), summary.json, report.md and report.html into `dir`.
void writeDemoReport(const std::string& dir, const DemoResult& result,
                     const std::vector<Figure>& figures);

}  // namespace dynid
