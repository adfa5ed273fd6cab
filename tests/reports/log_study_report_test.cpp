// dynid study's conclusions (every branch of the rules, no sentence recommending an inconsistent
// estimate) and its figure (names as written, coinciding points merged).
#include "reports/log_study_report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "data/io.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/study_rows.hpp"

namespace dynid {
namespace {

constexpr auto row = test::studyRow;

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

LogStudyOutcome outcome(std::vector<LogStudyRow> rows) {
  LogStudyOutcome o;
  o.robot_spec = "puma560";
  o.data_file = "train.csv";
  o.validate_file = "test.csv";
  o.rows = std::move(rows);
  const LogStudyRequest defaults;  // the settings logStudyRun records
  o.drive_terms = "none";
  o.segments = defaults.segments;
  o.prior_weight = defaults.prior_weight;
  o.combined_weight = defaults.combined_weight;
  o.refine_seconds = defaults.refine_seconds;
  o.refine_iterations = defaults.refine_iterations;
  return o;
}

TEST(LogStudyConclusions, RecommendOnlyConsistentEstimatesAndNeverContradict) {
  LogStudyOutcome o = outcome({row("model", 0.04, 1090.0, true), row("ols", 0.0102, 6e6, false),
                               row("pc", 0.0108, 85.9, true), row("nlo", 0.0187, 33.5, false),
                               row("combined", 0.0112, 40.0, true)});
  std::string text = joined(logStudyConclusions(o));
  EXPECT_NE(text.find("For simulation (forward dynamics), use combined"), std::string::npos)
      << text;
  EXPECT_NE(text.find("For control and monitoring (feed-forward torques), use pc"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("ols fits the held-out torques best"), std::string::npos) << text;
  EXPECT_NE(text.find("nlo predicts the held-out motion best"), std::string::npos) << text;
  EXPECT_NE(text.find("not physically consistent, so it is not recommended"), std::string::npos);
  EXPECT_NE(text.find("combined lowers it"), std::string::npos) << text;
  for (const char* inconsistent : {"use ols", "use nlo"})
    EXPECT_EQ(text.find(inconsistent), std::string::npos) << text;

  // One consistent estimate best at both.
  o.rows[4].torque_test = 0.0105;
  text = joined(logStudyConclusions(o));
  EXPECT_NE(text.find("Use combined for simulation and for control"), std::string::npos) << text;
  EXPECT_EQ(text.find("For simulation"), std::string::npos) << text;

  // No consistent estimate: nothing recommended.
  o = outcome({row("ols", 0.01, 6e6, false), row("nlo", 0.02, 30.0, false)});
  text = joined(logStudyConclusions(o));
  EXPECT_NE(text.find("none is recommended"), std::string::npos) << text;
  for (const char* advice : {"Use ", "use ols", "use nlo", "For simulation"})
    EXPECT_EQ(text.find(advice), std::string::npos) << text;
}

TEST(LogStudyConclusions, SayWhichRowsDidNotMove) {
  LogStudyOutcome o = outcome({row("pc", 0.01, 80.0, true), row("nlo", 0.02, 30.0, false),
                               row("nlo_refined", 0.02, 30.0, false)});
  o.rows[2].moved = false;
  o.rows[2].note = "the refinement ended at the search's result (...)";
  const std::string text = joined(logStudyConclusions(o));
  EXPECT_NE(text.find("nlo_refined did not move from its start: the refinement ended"),
            std::string::npos)
      << text;
}

// A least-squares residual with friction's shape, and a model without those drive terms: a
// conclusion says which terms are missing and the option; with them, nothing.
TEST(LogStudyConclusions, SayWhenTheResidualHasTheShapeOfMissingFriction) {
  LogStudyOutcome o = outcome({row("ols", 0.09, 5e7, false), row("pc", 0.09, 1e5, true)});
  o.fit_reversals.samples = 100;
  o.fit_reversals.friction_share = Eigen::Vector2d(0.95, 0.1);
  o.fit_reversals.friction_flagged = {0};
  std::string text = joined(logStudyConclusions(o));
  EXPECT_NE(text.find("Missing friction: Fc sign(dq) + Fv dq + Fo, fitted to the least-squares "
                      "estimate's training residual, explains 95 % of it on joint 1"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("--drive-terms fv,fc,fo adds them"), std::string::npos) << text;
  o.drive_terms = "fv,fc,fo";
  text = joined(logStudyConclusions(o));
  EXPECT_EQ(text.find("Missing friction"), std::string::npos) << text;
}

TEST(LogStudyReport, FigureWritesNamesAsWrittenAndMergesCoincidingPoints) {
  // gnuplot is installed by scripts/install-deps.sh.
  const LogStudyOutcome o =
      outcome({row("pc", 0.011, 85.9, true), row("nlo", 0.0187, 33.5, false),
               row("nlo_refined", 0.0187, 33.5, false), row("ga_refined", 0.0266, 42.7, false)});
  const Document doc = logStudyDocument(o);
  ASSERT_EQ(doc.figures().size(), 1u);
  const std::string& svg = doc.figures().front().svg;
  // Enhanced text would split "ga_refined" into "ga" and a subscript "r" in separate tspans.
  EXPECT_NE(svg.find("ga_refined"), std::string::npos);
  EXPECT_NE(svg.find("nlo = nlo_refined"), std::string::npos);
  EXPECT_EQ(svg.find(">r</tspan>"), std::string::npos);
}

TEST(LogStudyReport, OpensWithAVerdictThatRecommendsOnlyAConsistentEstimate) {
  // nlo fits the held-out torques best but is not consistent: the verdict names pc for both.
  const LogStudyOutcome o =
      outcome({row("pc", 0.011, 85.9, true), row("nlo", 0.0100, 33.5, false)});
  const std::string md = logStudyDocument(o).markdown();
  EXPECT_LT(md.find("> **Verdict**"), md.find("## Comparison")) << md;
  EXPECT_NE(md.find("> - **How well:** use pc for simulation and for control: held-out torque "
                    "error 1.1 %"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.substr(0, md.find("## Comparison")).find("nlo"), std::string::npos) << md;
  // None consistent: none recommended.
  const std::string none = logStudyDocument(outcome({row("nlo", 0.0100, 33.5, false)})).markdown();
  EXPECT_NE(none.find("no physically consistent estimate finished"), std::string::npos) << none;
}

TEST(LogStudyReport, NextGivesTheIdentifyRunOfTheRecommendedEstimate) {
  // combined recommended: identify's request with the study's inputs and the settings that differ
  // from identify's defaults, a write-back into its out for a URDF; by field name unless the
  // caller spells it (the CLI: tests/cli/command_study_test.cpp).
  LogStudyOutcome o = outcome({row("pc", 0.011, 85.9, true), row("combined", 0.0112, 40.0, true)});
  o.robot_spec = "my arm.urdf";
  o.drive_terms = "fv,fc,fo";
  o.refine_seconds = 20.0;
  const std::optional<StudyRepeat> r = studyRepeat(o);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->method, "combined");
  EXPECT_EQ(r->combined_seconds, 20.0);
  EXPECT_FALSE(r->combined_weight || r->combined_iterations || r->segments || r->prior_weight);
  EXPECT_EQ(r->write_urdf, "combined/identified.urdf");
  const std::string md = logStudyDocument(o).markdown();
  EXPECT_NE(md.find("`identify with method = combined, robot_spec = my arm.urdf, drive_terms = "
                    "fv,fc,fo, data_file = train.csv, validate_file = test.csv, out = combined, "
                    "combined_seconds = 20, write_urdf = combined/identified.urdf` writes it into "
                    "a copy of the URDF"),
            std::string::npos)
      << md;
  // A caller's spelling is what the report writes.
  const std::string spelt =
      logStudyDocument(o, [](const StudyRepeat& x) { return "run " + x.method; }).markdown();
  EXPECT_NE(spelt.find("`run combined` writes it"), std::string::npos) << spelt;
  // The input model recommended: nothing to identify.
  const LogStudyOutcome model_best =
      outcome({row("model", 0.01, 30.0, true), row("pc", 0.02, 80.0, true)});
  EXPECT_FALSE(studyRepeat(model_best));
  EXPECT_NE(logStudyDocument(model_best)
                .markdown()
                .find("the input model itself is the recommended one: use puma560 as it is"),
            std::string::npos);
  // pc on a built-in robot: no write-back, the default settings left out.
  const std::string pc = logStudyDocument(outcome({row("pc", 0.011, 85.9, true)})).markdown();
  EXPECT_NE(pc.find("`identify with method = pc, robot_spec = puma560, drive_terms = none, "
                    "data_file = train.csv, validate_file = test.csv, out = pc` writes it;"),
            std::string::npos)
      << pc;
}

TEST(LogStudyReport, WithAFrontItOpensWithTheChoiceAndKeepsEveryPoint) {
  LogStudyOutcome o = outcome({row("model", 0.04, 2600.0, true), row("pc", 0.0108, 1050.0, true),
                               row("nlo", 0.0188, 116.0, false)});
  o.drive_terms = "fv,fc,fo";
  o.front_tolerance = 0.05;
  o.front = {{0.3, row("front", 0.0109, 121.0, true)},
             {1.0, row("front", 0.0111, 61.0, true)},
             {10.0, row("front", 0.0116, 21.4, true)}};
  const Document doc = logStudyDocument(o);
  const std::string md = doc.markdown();
  // The point at w = 1 (1.11 % <= 1.05 x 1.08 %) predicts best within the bound.
  EXPECT_NE(md.find("> - **Chosen:** the front's point at w = 1 (held-out torque error 1.11 %, GC "
                    "error 61)"),
            std::string::npos)
      << md;
  // The chosen estimate is chosen.json; identify --front repeats the sweep, and here its choice
  // among the front's points alone (bound 1.05 x 1.09 %) is the same point.
  EXPECT_NE(md.find("the chosen estimate is in chosen.json"), std::string::npos) << md;
  EXPECT_NE(md.find("validate_file = test.csv, out = combined, front_weights = 0.3,1,10` sweeps "
                    "the same front and writes its estimate.json (the same point)"),
            std::string::npos)
      << md;
  EXPECT_TRUE(studyRepeat(o)->front);
  EXPECT_FALSE(studyRepeat(o)->front_differs);
  EXPECT_FALSE(studyRepeat(o)->combined_weight);
  EXPECT_NE(md.find("## The front"), std::string::npos);
  EXPECT_NE(md.find("| 10 | 1.16 % | 1.16 % | 21.4 | 21.4 | 0 | yes |"), std::string::npos) << md;
  const nlohmann::json j = logStudyJson(o);
  EXPECT_EQ(j["schema_version"], 5);
  ASSERT_EQ(j["front"]["points"].size(), 3u);
  EXPECT_EQ(j["choice"]["estimate"], "chosen.json");
  EXPECT_EQ(j["front"]["points"][2]["weight"], 10.0);
  EXPECT_EQ(j["choice"]["key"], "front");
  EXPECT_EQ(j["choice"]["front_weight"], 1.0);
  EXPECT_EQ(j["choice"]["best_torque"], "pc");
  // The figure draws the front and rings the chosen point.
  ASSERT_EQ(doc.figures().size(), 1u);
  EXPECT_NE(doc.figures().front().svg.find("front"), std::string::npos);
  // front.csv beside the report: a row per point.
  const std::string dir = test::tempPath("front_report");
  writeLogStudy(dir, o);
  const std::string csv = readFile(dir + "/front.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  EXPECT_EQ(csv.rfind("weight,torque_relative_error_train,", 0), 0u) << csv;
  EXPECT_NE(csv.find("\n10,0.0116"), std::string::npos) << csv;
  // Another point chosen by the study than by identify's rule: pc's 1.08 % sets the study's bound
  // (1.134 %), the front's best 1.10 % identify's (1.155 %), which lets w = 1 in.
  o.front[0].row.torque_test = 0.0110;
  o.front[1].row.torque_test = 0.0114;
  EXPECT_EQ(studyChoice(o, 0.05).front_index, 0);
  EXPECT_TRUE(studyRepeat(o)->front_differs);
  EXPECT_NE(logStudyDocument(o).markdown().find("choosing among the front's points alone: here "
                                                "another point than this study's"),
            std::string::npos);
  // Every candidate at its noise floor: the sentence says the motion cannot tell them apart.
  LogStudyOutcome floor = o;
  for (LogStudyRow& r : floor.rows) r.gc_floor_test = r.gc_test;
  for (FrontRow& f : floor.front) f.row.gc_floor_test = f.row.gc_test;
  const std::string at_floor = logStudyDocument(floor).markdown();
  EXPECT_NE(at_floor.find("the motion cannot tell them apart, so the least held-out torque error "
                          "decides"),
            std::string::npos)
      << at_floor;
  EXPECT_EQ(logStudyJson(floor)["choice"]["key"], "pc");  // 1.08 %, the least torque error
  EXPECT_TRUE(logStudyJson(floor)["choice"]["at_noise_floor"].get<bool>());
  // Other weights and tolerance than the defaults are repeated; the default sweep is --front.
  o.front_tolerance = 0.1;
  EXPECT_EQ(studyRepeat(o)->front_tolerance, 0.1);
  EXPECT_EQ(studyRepeat(o)->front_weights, (std::vector<double>{0.3, 1.0, 10.0}));
}

}  // namespace
}  // namespace dynid
