// Labels for scatter figures (the study's torque-against-GC figure): each point's name beside it,
// no two labels overlapping, none over a marker and every one inside the plot, in the figure's
// pixel coordinates (y up, as gnuplot's screen coordinates); the figure converts them to graph
// coordinates for gnuplot. Greedy: each label in turn takes the first free place on rings of
// growing distance around its point (right, left, above, below, then the diagonals and finer
// directions), with a leader line from the point when it is not next to it.
#pragma once

#include <string>
#include <vector>

namespace dynid {

struct LabelArea {
  double left = 0.0, right = 0.0, bottom = 0.0, top = 0.0;  // pixels
};
/// How large a label and a marker are [pixels]: a conservative width per character of the
/// figure's 10-point sans font ("combined (chosen)" is 118 px drawn, 6.9 a character), its line
/// height, a marker's half-size (the chosen estimate's ring's, its line included, with room: 11 px)
/// and the gap kept between labels, markers and the area's edge.
struct LabelMetrics {
  double char_width = 7.0, height = 13.0, marker = 11.0, gap = 3.0;
};
struct LabelBox {
  double left = 0.0, bottom = 0.0, width = 0.0, height = 0.0;
  double right() const { return left + width; }
  double top() const { return bottom + height; }
};
struct PlacedLabel {
  bool placed = false;  // false: no free place within the area (the figure lists it instead)
  LabelBox box;         // the text's box: drawn left-aligned at (left, bottom + height / 2)
  bool leader = false;  // a line from the point to the box (the box is not next to it)
};
struct LabelPoint {
  double x = 0.0, y = 0.0;  // the point [pixels]
  std::string text;
};

/// One label per point of `points`, in their order (the earlier get the nearer places); the
/// markers of `points` and of `obstacles` (points drawn without a label) are kept clear.
std::vector<PlacedLabel> placeLabels(const std::vector<LabelPoint>& points,
                                     const std::vector<LabelPoint>& obstacles,
                                     const LabelArea& area, const LabelMetrics& metrics = {});

/// Whether two boxes overlap (touching edges do not).
bool boxesOverlap(const LabelBox& a, const LabelBox& b);

}  // namespace dynid
