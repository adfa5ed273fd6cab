#include "reports/label_layout.hpp"

#include <cmath>
#include <numbers>

namespace dynid {

bool boxesOverlap(const LabelBox& a, const LabelBox& b) {
  return a.left < b.right() && b.left < a.right() && a.bottom < b.top() && b.bottom < a.top();
}

namespace {

/// The box of a label `width` x `height` whose side facing its point lies `distance` from it in
/// the direction `angle` (0: right of the point, centred on it vertically).
LabelBox boxAt(const LabelPoint& p, double angle, double distance, double width, double height) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double centre_x = p.x + distance * c + 0.5 * width * c;
  const double centre_y = p.y + distance * s + 0.5 * height * s;
  return {centre_x - 0.5 * width, centre_y - 0.5 * height, width, height};
}

/// A marker as a box, the gap around it included.
LabelBox markerBox(const LabelPoint& p, const LabelMetrics& m) {
  const double half = m.marker + m.gap;
  return {p.x - half, p.y - half, 2.0 * half, 2.0 * half};
}

/// A box grown by the gap on every side.
LabelBox padded(const LabelBox& b, double gap) {
  return {b.left - gap, b.bottom - gap, b.width + 2.0 * gap, b.height + 2.0 * gap};
}

/// The directions tried on each ring: the four sides first, then the diagonals, then finer.
std::vector<double> directions(int ring) {
  constexpr double pi = std::numbers::pi;
  std::vector<double> out = {0.0, pi, 0.5 * pi, 1.5 * pi};
  for (int k = 0; k < 4; ++k) out.push_back((0.25 + 0.5 * k) * pi);
  if (ring > 0)
    for (int k = 0; k < 8; ++k) out.push_back((0.125 + 0.25 * k) * pi);
  return out;
}

}  // namespace

std::vector<PlacedLabel> placeLabels(const std::vector<LabelPoint>& points,
                                     const std::vector<LabelPoint>& obstacles,
                                     const LabelArea& area, const LabelMetrics& m) {
  std::vector<LabelBox> taken;  // markers (padded) and placed labels (padded)
  for (const LabelPoint& p : points) taken.push_back(markerBox(p, m));
  for (const LabelPoint& p : obstacles) taken.push_back(markerBox(p, m));
  const auto inside = [&](const LabelBox& b) {
    return b.left >= area.left + m.gap && b.right() <= area.right - m.gap &&
           b.bottom >= area.bottom + m.gap && b.top() <= area.top - m.gap;
  };
  const auto free = [&](const LabelBox& b) {
    if (!inside(b)) return false;
    for (const LabelBox& t : taken)
      if (boxesOverlap(b, t)) return false;
    return true;
  };
  const double first = m.marker + m.gap;  // next to the marker
  const double step = m.height;           // each further ring
  const double reach = std::hypot(area.right - area.left, area.top - area.bottom);
  std::vector<PlacedLabel> out;
  for (const LabelPoint& p : points) {
    const double width = m.char_width * static_cast<double>(p.text.size());
    PlacedLabel label;
    for (int ring = 0; !label.placed && first + ring * step <= reach; ++ring)
      for (double angle : directions(ring)) {
        const LabelBox box = boxAt(p, angle, first + ring * step, width, m.height);
        if (!free(box)) continue;
        label = {true, box, ring > 0};
        taken.push_back(padded(box, m.gap));
        break;
      }
    out.push_back(label);
  }
  return out;
}

}  // namespace dynid
