// The figures' label placement: no two labels overlap, none covers a marker, every one inside its
// area, the first free place next to its point taken first.
#include "reports/label_layout.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dynid {
namespace {

/// Every placed label inside `area`, clear of the other labels and of every marker.
void expectClear(const std::vector<PlacedLabel>& labels, const std::vector<LabelPoint>& points,
                 const std::vector<LabelPoint>& obstacles, const LabelArea& area) {
  const LabelMetrics m;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!labels[i].placed) continue;
    const LabelBox& b = labels[i].box;
    EXPECT_GE(b.left, area.left);
    EXPECT_LE(b.right(), area.right);
    EXPECT_GE(b.bottom, area.bottom);
    EXPECT_LE(b.top(), area.top);
    for (std::size_t j = i + 1; j < labels.size(); ++j)
      if (labels[j].placed) EXPECT_FALSE(boxesOverlap(b, labels[j].box)) << i << " and " << j;
    std::vector<LabelPoint> markers = points;
    markers.insert(markers.end(), obstacles.begin(), obstacles.end());
    for (const LabelPoint& p : markers)
      EXPECT_FALSE(boxesOverlap(b, {p.x - m.marker, p.y - m.marker, 2 * m.marker, 2 * m.marker}))
          << points[i].text << " covers the marker at " << p.x << ", " << p.y;
  }
}

TEST(LabelLayout, AnIsolatedPointIsNamedRightBesideIt) {
  const LabelArea area{0, 400, 0, 300};
  const std::vector<LabelPoint> points = {{100, 100, "pc"}};
  const std::vector<PlacedLabel> labels = placeLabels(points, {}, area);
  ASSERT_TRUE(labels[0].placed);
  EXPECT_FALSE(labels[0].leader);
  const LabelMetrics m;
  EXPECT_DOUBLE_EQ(labels[0].box.left, 100 + m.marker + m.gap);  // right of the marker
  EXPECT_DOUBLE_EQ(labels[0].box.bottom + 0.5 * labels[0].box.height, 100.0);
  // At the right edge the name goes to the left.
  const std::vector<PlacedLabel> edge = placeLabels({{395, 100, "pc"}}, {}, area);
  ASSERT_TRUE(edge[0].placed);
  EXPECT_LT(edge[0].box.right(), 395.0);
}

// The case: eleven names in a blob (some merged names long), one point far away, the
// front's points as unnamed markers among them.
TEST(LabelLayout, ABlobOfNamesGetsPlacesNoneOverlapping) {
  const LabelArea area{80, 530, 55, 500};
  std::vector<LabelPoint> points = {{100, 480, "model"}};
  const char* names[] = {"ols",
                         "wls",
                         "pc",
                         "start = pc",
                         "nlo = hybrid = ga",
                         "ga_refined",
                         "nlo_refined",
                         "hybrid_refined",
                         "combined",
                         "front, w = 100",
                         "chosen, w = 1"};
  for (int k = 0; k < 11; ++k)
    points.push_back({300.0 + 9.0 * (k % 4), 120.0 + 7.0 * (k / 4), names[k]});
  std::vector<LabelPoint> front;
  for (int k = 0; k < 6; ++k) front.push_back({295.0 + 4.0 * k, 110.0 + 5.0 * k, ""});
  const std::vector<PlacedLabel> labels = placeLabels(points, front, area);
  for (const PlacedLabel& l : labels) EXPECT_TRUE(l.placed);
  expectClear(labels, points, front, area);
  // The crowd pushes most names off their points: those get leader lines.
  int leaders = 0;
  for (const PlacedLabel& l : labels) leaders += l.leader ? 1 : 0;
  EXPECT_GT(leaders, 0);
}

TEST(LabelLayout, ANameWiderThanTheAreaIsLeftUnplaced) {
  const LabelArea area{0, 100, 0, 100};
  const std::vector<PlacedLabel> labels =
      placeLabels({{50, 50, std::string(40, 'x')}, {20, 20, "pc"}}, {}, area);
  EXPECT_FALSE(labels[0].placed);  // 260 px of text in a 100 px area
  EXPECT_TRUE(labels[1].placed);   // the others are still named
}

}  // namespace
}  // namespace dynid
