// The study's figure, torque_vs_gc.svg: each model's held-out torque error against its held-out
// GC error (log-log), the front as a line, the chosen estimate ringed. When the physically
// consistent estimates cluster far from the rest (an input model at GC 1e8 beside eleven models
// within two decades), a second panel zooms on them and the first marks the zoomed window; every
// name is placed by reports/label_layout.hpp, so that no two overlap.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/studies/log_study.hpp"
#include "reports/label_layout.hpp"

namespace dynid {

/// A panel of the figure: its plot area [pixels of the canvas, y up] and its log10 ranges.
struct StudyPanel {
  std::string title;
  LabelArea area;
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;  // log10 of the axes' ends
};
/// Where everything goes, before gnuplot draws it: the canvas, the panels (one, or the whole and
/// the zoom), each point's label placed in the panel that names it.
struct StudyFigureLayout {
  int width = 800, height = 520;
  std::vector<StudyPanel> panels;
  struct Point {
    std::string label;  // empty: drawn, not named (the front's points)
    double torque_percent = 0.0, gc = 0.0;
  };
  std::vector<Point> points;  // the rows (coinciding ones merged), then the front's named points
  /// Per panel, per point: its label (placed false: not named in that panel).
  std::vector<std::vector<PlacedLabel>> labels;
  std::vector<std::string> unplaced;  // names no panel had room for (listed under the figure)
};
/// The layout of `outcome`'s figure; no panels when no model has finite positive errors.
StudyFigureLayout studyFigureLayout(const LogStudyOutcome& outcome);

/// The SVG, or nullopt when there is nothing to draw or gnuplot did not run.
std::optional<std::string> studyFigure(const LogStudyOutcome& outcome);

}  // namespace dynid
