// The study's figure: one panel when the models spread evenly, a zoom on the physically consistent
// estimates when they cluster far from the rest, every name placed once and none overlapping.
#include "reports/log_study_figure.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "tests/common/study_rows.hpp"

namespace dynid {
namespace {

constexpr auto figureRow = test::studyRow;

/// The current-sensing arm: the input model at GC 1e8, eleven models within two decades
/// (searches and refinements coinciding), the front between pc and the best GC.
LogStudyOutcome clustered() {
  LogStudyOutcome o;
  o.rows = {
      figureRow("model", 0.40, 1e8, true),          figureRow("ols", 0.0490, 3.9, false),
      figureRow("wls", 0.0492, 4.1, false),         figureRow("pc", 0.0490, 3.6, true),
      figureRow("start", 0.0490, 3.6, true),        figureRow("nlo", 0.0560, 3.4, false),
      figureRow("nlo_refined", 0.0560, 3.4, false), figureRow("ga", 0.0570, 3.5, false),
      figureRow("hybrid", 0.0561, 3.41, false),     figureRow("ga_refined", 0.0530, 3.45, false),
      figureRow("combined", 0.0501, 2.13, true)};
  o.front_tolerance = 0.05;
  const double weights[] = {0.01, 0.1, 1, 10, 100};
  for (int k = 0; k < 5; ++k)
    o.front.push_back({weights[k], figureRow("front", 0.0490 + 0.0004 * k, 3.5 - 0.4 * k, true)});
  return o;
}

/// Every label placed in a panel lies inside it and overlaps no other in that panel.
void expectNoOverlap(const StudyFigureLayout& l) {
  for (std::size_t p = 0; p < l.panels.size(); ++p) {
    const LabelArea& a = l.panels[p].area;
    const std::vector<PlacedLabel>& labels = l.labels[p];
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (!labels[i].placed) continue;
      EXPECT_GE(labels[i].box.left, a.left);
      EXPECT_LE(labels[i].box.right(), a.right);
      for (std::size_t j = i + 1; j < labels.size(); ++j)
        if (labels[j].placed)
          EXPECT_FALSE(boxesOverlap(labels[i].box, labels[j].box))
              << l.points[i].label << " and " << l.points[j].label << " in panel " << p;
    }
  }
}

TEST(LogStudyFigure, ZoomsOnTheConsistentEstimatesWhenTheyClusterFarFromTheRest) {
  const StudyFigureLayout l = studyFigureLayout(clustered());
  ASSERT_EQ(l.panels.size(), 2u);
  EXPECT_EQ(l.width, 1100);
  // The zoom spans the consistent estimates (pc, combined, the front), not the input model's 1e8.
  EXPECT_LT(l.panels[1].y1, 1.0);
  EXPECT_GT(l.panels[0].y1, 8.0);
  expectNoOverlap(l);
  EXPECT_TRUE(l.unplaced.empty());
  // Each name is placed exactly once: the input model in the whole, the cluster in the zoom.
  for (std::size_t k = 0; k < l.points.size(); ++k) {
    if (l.points[k].label.empty()) continue;
    const int placed = (l.labels[0][k].placed ? 1 : 0) + (l.labels[1][k].placed ? 1 : 0);
    EXPECT_EQ(placed, 1) << l.points[k].label;
  }
  const auto named = [&](const std::string& text, std::size_t panel) {
    for (std::size_t k = 0; k < l.points.size(); ++k)
      if (l.points[k].label == text) return l.labels[panel][k].placed;
    return false;
  };
  EXPECT_TRUE(named("model", 0));
  EXPECT_TRUE(named("pc = start", 1));  // coinciding rows share one point and one name
  // The searches (not consistent, outside the zoom) are named in the whole; nlo, its refinement
  // and hybrid coincide within 0.5 %.
  EXPECT_TRUE(named("nlo = nlo_refined = hybrid", 0));
  EXPECT_TRUE(named("chosen, w = 100", 1));  // the least GC within 5 % of the best torque fit
  // Drawn: both panels' titles, every name once.
  const std::optional<std::string> svg = studyFigure(clustered());
  ASSERT_TRUE(svg);
  EXPECT_NE(svg->find("zoom: the physically consistent estimates"), std::string::npos);
  EXPECT_NE(svg->find("every model"), std::string::npos);
  EXPECT_NE(svg->find("chosen, w = 100"), std::string::npos);
}

TEST(LogStudyFigure, OnePanelWhenTheModelsSpreadEvenly) {
  LogStudyOutcome o;
  o.rows = {figureRow("model", 0.04, 2600.0, true), figureRow("pc", 0.0108, 1050.0, true),
            figureRow("nlo", 0.0188, 116.0, false), figureRow("combined", 0.0111, 61.0, true)};
  const StudyFigureLayout l = studyFigureLayout(o);
  ASSERT_EQ(l.panels.size(), 1u);
  expectNoOverlap(l);
  for (std::size_t k = 0; k < l.points.size(); ++k) EXPECT_TRUE(l.labels[0][k].placed);
  // Nothing drawable: no panel.
  LogStudyOutcome none;
  none.rows = {figureRow("pc", std::nan(""), 1.0, true)};
  EXPECT_TRUE(studyFigureLayout(none).panels.empty());
  EXPECT_FALSE(studyFigure(none));
}

}  // namespace
}  // namespace dynid
