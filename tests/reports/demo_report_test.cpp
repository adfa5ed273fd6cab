#include "reports/demo_report.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

namespace dynid {
namespace {

DemoResult sampleDemo() {
  DemoResult r;
  r.settings.robot = "puma560";
  r.settings.train_seconds = r.settings.test_seconds = 4.0;
  r.settings.segments = 20;
  r.identifiability.num_standard = 60;
  r.identifiability.num_base = 2;
  r.identifiability.base_names = {"Izz1R", "m2"};
  r.identifiability.base_expressions = {"Izz1 + Iyy2", "m2"};
  r.identifiability.unidentifiable = {"m1"};
  r.identifiability.condition_number = 142.5;
  MethodMetrics ols{"ols", 5.0, 1e-23, 2e-22, 3e-14, 49.2, 2e-12, 0, 0.02};
  MethodMetrics nlo{"nlo", 5.0, 0.1, 0.2, 0.3, 1.3, 0.5, 750, 2.0};
  nlo.gc_error_test = std::numeric_limits<double>::quiet_NaN();  // a diverged held-out rollout
  r.methods = {ols, nlo};
  return r;
}

TEST(DemoReport, SummaryJsonHasEveryFieldAndNullForNonFinite) {
  const auto j = nlohmann::json::parse(demoSummaryJson(sampleDemo()));
  EXPECT_EQ(j["schema_version"], 2);
  EXPECT_EQ(j["order"], (std::vector<std::string>{"ols", "nlo"}));
  EXPECT_EQ(j["methods"]["ols"]["base_param_error"].get<double>(), 2e-12);
  EXPECT_EQ(j["methods"]["nlo"]["evaluations"], 750);
  EXPECT_TRUE(j["methods"]["nlo"]["gc_error_test"].is_null());
  EXPECT_EQ(j["identifiability"]["num_base"], 2);
  EXPECT_EQ(j["identifiability"]["base_parameters"][0]["expression"], "Izz1 + Iyy2");
}

TEST(DemoReport, MarkdownAndHtmlCarryTheTableAndTheConclusions) {
  const DemoResult r = sampleDemo();
  const std::string md = demoMarkdown(r);
  EXPECT_NE(md.find("| ols | 5 | 1e-23 | 2e-22 | 3e-14 | 49.2 | 2e-12 | 0 | 0.02 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| nlo | 5 | 0.1 | n/a |"), std::string::npos) << md;
  EXPECT_NE(md.find("| Izz1R | Izz1 + Iyy2 |"), std::string::npos);
  EXPECT_NE(md.find("nlo cuts the training GC error 50x"), std::string::npos) << md;
  const std::string html = demoHtml(r);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // The verdict box opens both, before the (folded) base-parameter table and the comparison.
  EXPECT_LT(md.find("> **Verdict**"), md.find("## Identifiability"));
  EXPECT_NE(md.find("> - **Not determined:** "), std::string::npos) << md;
  EXPECT_LT(html.find("<section class=\"verdict\""), html.find("<h2>Identifiability</h2>"));
  EXPECT_LT(html.find("<details><summary>"), html.find("<table id=\"base\">"));
  EXPECT_NE(html.find("<tr><td>ols</td><td>5</td><td>1e-23</td>"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);
  const std::string table = demoTable(r);
  EXPECT_NE(table.find("ols"), std::string::npos);
  EXPECT_NE(table.find("n/a"), std::string::npos);
  // Every header whole (they were cut to 12 characters: "torque RMS t"), and every row as long
  // as the header line (the columns line up).
  EXPECT_NE(table.find(" torque RMS test [N m] "), std::string::npos) << table;
  EXPECT_NE(table.find(" base param error "), std::string::npos) << table;
  std::istringstream rows(table);
  std::string header, row;
  std::getline(rows, header);
  while (std::getline(rows, row)) EXPECT_EQ(row.size(), header.size()) << row;
}

TEST(DemoReport, FiguresFromGnuplotOrAWarningWithoutIt) {
  DemoResult r = sampleDemo();
  DemoSearchTrace trace;
  trace.method = "nlo";
  for (int i = 0; i < 5; ++i)
    trace.history.push_back({"nlo", i, 5.0 / (1 + 10 * i), 1.5, 1.0, 100L * i, 0.5 * i});
  trace.candidates = 500;
  trace.pearson_log = -0.3;
  trace.spearman = -0.25;
  r.initial_gc_test = 5.0;
  r.near_truth.gc_errors = {0.01, 0.02, 0.05, 0.1, 0.2};
  r.near_truth.estimate = "nlo";
  r.near_truth.estimate_gc = 0.04;
  r.near_truth.percentile = 40.0;
  trace.evaluated = {{0.1, 1.0}, {0.2, 1.5}, {0.05, 2.0}};
  r.searches = {trace};
  std::string warning;
  const std::vector<Figure> figures = demoFigures(r, &warning);
  // gnuplot is installed by scripts/install-deps.sh (gnuplot-nox): one figure per kind.
  ASSERT_EQ(figures.size(), 6u) << warning;
  for (const Figure& f : figures) {
    EXPECT_NE(f.svg.find("<svg"), std::string::npos) << f.name;
    EXPECT_FALSE(f.caption.empty()) << f.name;
  }
  EXPECT_NE(figures[1].caption.find("nlo r = -0.3"), std::string::npos) << figures[1].caption;
  EXPECT_NE(figures.back().caption.find("40 % of the near-truth"), std::string::npos)
      << figures.back().caption;
  const std::string html = demoHtml(r, figures);
  EXPECT_NE(html.find("<figure id=\"gc_error_iterations\">\n<svg"), std::string::npos);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);
  // Without gnuplot: no figures, a warning, no failure.
  ::setenv("DYNID_GNUPLOT", "/nonexistent/gnuplot", 1);
  warning.clear();
  EXPECT_TRUE(demoFigures(r, &warning).empty());
  EXPECT_NE(warning.find("gnuplot"), std::string::npos);
  ::unsetenv("DYNID_GNUPLOT");
  EXPECT_EQ(demoMarkdown(r, {}).find("## Figures"), std::string::npos);
}

}  // namespace
}  // namespace dynid
