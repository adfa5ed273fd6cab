#include "reports/log_study_figure.hpp"

#include <algorithm>
#include <cmath>

#include "core/format.hpp"
#include "reports/plot_script.hpp"

namespace dynid {

namespace {

bool drawable(double torque, double gc) {
  return std::isfinite(torque) && std::isfinite(gc) && torque > 0.0 && gc > 0.0;
}

/// The figure's points, and whether each is one the zoom is on (a physically consistent estimate:
/// a consistent row but the input model, or a point of the front).
struct Collected {
  std::vector<StudyFigureLayout::Point> points;
  std::vector<bool> zoom_member;
};

/// Rows whose held-out errors coincide (within 0.5 % in both: one point on the log-log figure)
/// share one point, labelled "nlo = nlo_refined"; the chosen one's label says so. The front's
/// points follow, unnamed but its last ("front, w = 100") and the chosen one ("chosen, w = 1").
Collected collect(const LogStudyOutcome& o) {
  Collected out;
  const auto close = [](double a, double b) { return std::abs(a - b) <= 0.005 * std::max(a, b); };
  const StudyChoice choice = studyChoice(o, o.front_tolerance);
  const bool front = !o.front.empty();
  for (const LogStudyRow& row : o.rows) {
    if (!drawable(row.torque_test, row.gc_test)) continue;
    const double t = 100.0 * row.torque_test;
    const bool chosen = front && choice.front_index < 0 && row.key == choice.key;
    std::string name = row.key;
    if (chosen) name += " (chosen)";
    const bool member = row.consistent && row.key != "model";
    bool merged = false;
    for (std::size_t k = 0; k < out.points.size() && !merged; ++k)
      if (close(out.points[k].torque_percent, t) && close(out.points[k].gc, row.gc_test)) {
        out.points[k].label += " = " + name;
        out.zoom_member[k] = out.zoom_member[k] || member;
        merged = true;
      }
    if (!merged) {
      out.points.push_back({name, t, row.gc_test});
      out.zoom_member.push_back(member);
    }
  }
  for (std::size_t k = 0; k < o.front.size(); ++k) {
    const LogStudyRow& r = o.front[k].row;
    if (!drawable(r.torque_test, r.gc_test)) continue;
    const std::string w = "w = " + formatNumber(o.front[k].weight, 3);
    std::string label;
    if (static_cast<int>(k) == choice.front_index)
      label = "chosen, " + w;
    else if (k + 1 == o.front.size())
      label = "front, " + w;
    out.points.push_back({label, 100.0 * r.torque_test, r.gc_test});
    out.zoom_member.push_back(true);
  }
  return out;
}

struct Window {
  double x0, x1, y0, y1;  // log10
  bool holds(double x, double y) const {
    const double lx = std::log10(x), ly = std::log10(y);
    return lx >= x0 && lx <= x1 && ly >= y0 && ly <= y1;
  }
};

/// The log10 window around the points `use` selects, padded by a tenth of its extent (at least
/// 0.05 decades: a tight cluster still gets room for its names).
Window windowOf(const Collected& c, const std::vector<bool>& use) {
  Window w{1e300, -1e300, 1e300, -1e300};
  for (std::size_t k = 0; k < c.points.size(); ++k)
    if (use[k]) {
      w.x0 = std::min(w.x0, std::log10(c.points[k].torque_percent));
      w.x1 = std::max(w.x1, std::log10(c.points[k].torque_percent));
      w.y0 = std::min(w.y0, std::log10(c.points[k].gc));
      w.y1 = std::max(w.y1, std::log10(c.points[k].gc));
    }
  const auto pad = [](double& lo, double& hi) {
    const double extent = std::max(hi - lo, 0.05);
    const double middle = 0.5 * (lo + hi);
    lo = middle - 0.5 * extent - 0.12 * extent;
    hi = middle + 0.5 * extent + 0.12 * extent;
  };
  pad(w.x0, w.x1);
  pad(w.y0, w.y1);
  return w;
}

/// A point's pixel position in a panel.
LabelPoint pixel(const StudyPanel& p, double x, double y, const std::string& text) {
  const LabelArea& a = p.area;
  return {a.left + (std::log10(x) - p.x0) / (p.x1 - p.x0) * (a.right - a.left),
          a.bottom + (std::log10(y) - p.y0) / (p.y1 - p.y0) * (a.top - a.bottom), text};
}

/// Whether to zoom: at least two consistent estimates, a point outside their window, and the
/// window less than half the whole in both axes (a cluster; a column of points spread over the GC
/// axis reads well as it is).
bool zoomWorthwhile(const Collected& c, const Window& all, const Window& zoom) {
  const long members = std::count(c.zoom_member.begin(), c.zoom_member.end(), true);
  bool outside = false;
  for (const auto& p : c.points) outside = outside || !zoom.holds(p.torque_percent, p.gc);
  return members >= 2 && outside && zoom.x1 - zoom.x0 < 0.5 * (all.x1 - all.x0) &&
         zoom.y1 - zoom.y0 < 0.5 * (all.y1 - all.y0);
}

}  // namespace

StudyFigureLayout studyFigureLayout(const LogStudyOutcome& o) {
  StudyFigureLayout out;
  const Collected c = collect(o);
  out.points = c.points;
  if (c.points.empty()) return out;
  const Window all = windowOf(c, std::vector<bool>(c.points.size(), true));
  const Window zoom = windowOf(c, c.zoom_member);
  const bool zoomed = zoomWorthwhile(c, all, zoom);
  const auto panel = [](const char* title, LabelArea area, const Window& w) {
    return StudyPanel{title, area, w.x0, w.x1, w.y0, w.y1};
  };
  if (zoomed) {
    out.width = 1100;
    out.height = 560;
    out.panels.push_back(
        panel("every model (the dashed box: the zoom at right)", {80, 530, 55, 500}, all));
    out.panels.push_back(
        panel("zoom: the physically consistent estimates", {630, 1080, 55, 500}, zoom));
  } else {
    out.panels.push_back(
        panel("held-out data: torque fit against motion prediction", {80, 780, 55, 480}, all));
  }
  for (std::size_t p = 0; p < out.panels.size(); ++p) {
    // The whole names what the zoom does not show; the zoom names what it shows.
    std::vector<LabelPoint> named, unnamed;
    std::vector<std::size_t> index;
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      const auto& q = c.points[k];
      const bool in_zoom = zoomed && zoom.holds(q.torque_percent, q.gc);
      const bool shown = p == 0 || in_zoom;
      if (!shown) continue;
      const LabelPoint at = pixel(out.panels[p], q.torque_percent, q.gc, q.label);
      const bool name_here = !q.label.empty() && (p == 1 || !in_zoom);
      if (name_here) {
        named.push_back(at);
        index.push_back(k);
      } else {
        unnamed.push_back(at);
      }
    }
    const std::vector<PlacedLabel> placed = placeLabels(named, unnamed, out.panels[p].area);
    std::vector<PlacedLabel> row(c.points.size());
    for (std::size_t i = 0; i < placed.size(); ++i) {
      row[index[i]] = placed[i];
      if (!placed[i].placed) out.unplaced.push_back(c.points[index[i]].label);
    }
    out.labels.push_back(row);
  }
  return out;
}

namespace {

/// A pixel position as gnuplot graph coordinates of the panel.
void graphAt(PlotScript& s, const StudyPanel& p, double x, double y) {
  s << "graph " << (x - p.area.left) / (p.area.right - p.area.left) << ", graph "
    << (y - p.area.bottom) / (p.area.top - p.area.bottom);
}

/// Tic values for a log axis from 10^lo to 10^hi: gnuplot's own (the decades) over two decades
/// or more; 1, 2, 5 in each decade over half a decade or more; below that a linear step of 1, 2
/// or 5 times a power of ten, four to ten tics (gnuplot's log axis would show none).
std::vector<double> logTics(double lo, double hi) {
  std::vector<double> out;
  if (hi - lo >= 2.0) return out;
  const double a = std::pow(10.0, lo), b = std::pow(10.0, hi);
  if (hi - lo >= 0.5) {
    for (int e = static_cast<int>(std::floor(lo)); e <= static_cast<int>(std::ceil(hi)); ++e)
      for (double m : {1.0, 2.0, 5.0})
        if (const double v = m * std::pow(10.0, e); v >= a && v <= b) out.push_back(v);
    return out;
  }
  const double raw = (b - a) / 5.0, power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * power;
  for (double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  for (double v = std::ceil(a / step) * step; v <= b; v += step) out.push_back(v);
  return out;
}

/// The tics of one axis: `set xtics (...)` or `set ytics (...)`, or gnuplot's own.
void writeTics(PlotScript& s, bool x, double lo, double hi) {
  const std::vector<double> tics = logTics(lo, hi);
  if (x)
    s << "set format x '%g'\nset xtics ";
  else
    s << "set format y '%g'\nset ytics ";
  if (tics.empty()) {
    s << "autofreq\n";
    return;
  }
  s << "(";
  for (std::size_t k = 0; k < tics.size(); ++k) {
    if (k > 0) s << ", ";
    s << tics[k];
  }
  s << ")\n";
}

/// One panel: its margins, ranges, the placed labels with their leaders, and the data.
void drawPanel(PlotScript& s, const StudyFigureLayout& l, std::size_t p, bool has_front,
               bool has_chosen, const StudyPanel* zoom_box) {
  const StudyPanel& panel = l.panels[p];
  const double w = l.width, h = l.height;
  s << "set lmargin at screen " << panel.area.left / w << "\nset rmargin at screen "
    << panel.area.right / w << "\nset bmargin at screen " << panel.area.bottom / h
    << "\nset tmargin at screen " << panel.area.top / h << "\n";
  s << "set xrange [" << std::pow(10.0, panel.x0) << ":" << std::pow(10.0, panel.x1) << "]\n"
    << "set yrange [" << std::pow(10.0, panel.y0) << ":" << std::pow(10.0, panel.y1) << "]\n"
    << "set title " << gnuplotString(panel.title) << "\n";
  writeTics(s, true, panel.x0, panel.x1);
  writeTics(s, false, panel.y0, panel.y1);
  int index = 1;
  for (std::size_t k = 0; k < l.points.size(); ++k) {
    const PlacedLabel& label = l.labels[p][k];
    if (!label.placed) continue;
    const LabelBox& b = label.box;
    s << "set label " << index++ << " " << gnuplotString(l.points[k].label) << " at ";
    graphAt(s, panel, b.left, b.bottom + 0.5 * b.height);
    s << " left font 'sans,10'\n";
    if (!label.leader) continue;
    const LabelPoint at = pixel(panel, l.points[k].torque_percent, l.points[k].gc, "");
    s << "set arrow from ";
    graphAt(s, panel, at.x, at.y);
    s << " to ";
    graphAt(s, panel, std::clamp(at.x, b.left, b.right()), std::clamp(at.y, b.bottom, b.top()));
    s << " nohead lw 0.8 lc rgb '#999999'\n";
  }
  if (zoom_box != nullptr) {
    // The zoomed window, drawn at least 24 px wide and high so that it shows around its points.
    const LabelPoint a =
        pixel(panel, std::pow(10.0, zoom_box->x0), std::pow(10.0, zoom_box->y0), "");
    const LabelPoint b =
        pixel(panel, std::pow(10.0, zoom_box->x1), std::pow(10.0, zoom_box->y1), "");
    const double grow_x = std::max(0.0, 24.0 - (b.x - a.x)) / 2.0;
    const double grow_y = std::max(0.0, 24.0 - (b.y - a.y)) / 2.0;
    s << "set object 1 rect from ";
    graphAt(s, panel, a.x - grow_x, a.y - grow_y);
    s << " to ";
    graphAt(s, panel, b.x + grow_x, b.y + grow_y);
    s << " fs empty border lc rgb '#888888' dt 2\n";
  }
  s << "plot $m using 1:2 with points pt 7 ps 1.2 lc rgb '#4477aa'";
  if (has_front) s << ", $f using 1:2 with linespoints pt 6 ps 0.9 lw 1.5 lc rgb '#cc6677'";
  if (has_chosen) s << ", $c using 1:2 with points pt 6 ps 2 lw 2 lc rgb '#222222'";
  s << "\nunset label\nunset arrow\nunset object\n";
}

}  // namespace

std::optional<std::string> studyFigure(const LogStudyOutcome& o) {
  const StudyFigureLayout l = studyFigureLayout(o);
  if (l.panels.empty()) return std::nullopt;
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size " << l.width << "," << l.height
    << " font 'sans,11' background rgb 'white'\n"
    << "set logscale xy\nset grid\nset key off\nset xlabel 'relative torque error [%]'\n"
    << "set ylabel 'GC error'\n";
  PlotRows rows, front, chosen;
  for (const LogStudyRow& r : o.rows)
    if (drawable(r.torque_test, r.gc_test)) rows.append({100.0 * r.torque_test, r.gc_test});
  for (const FrontRow& f : o.front)
    if (drawable(f.row.torque_test, f.row.gc_test))
      front.append({100.0 * f.row.torque_test, f.row.gc_test});
  if (!o.front.empty())
    if (const LogStudyRow* r = studyChosenRow(o, studyChoice(o, o.front_tolerance));
        r != nullptr && drawable(r->torque_test, r->gc_test))
      chosen.append({100.0 * r->torque_test, r->gc_test});
  s << "$m << EOD\n" << rows << "EOD\n";
  if (!front.text().empty()) s << "$f << EOD\n" << front << "EOD\n";
  if (!chosen.text().empty()) s << "$c << EOD\n" << chosen << "EOD\n";
  const bool zoomed = l.panels.size() == 2;
  if (zoomed) s << "set multiplot title 'held-out data: torque fit against motion prediction'\n";
  if (!l.unplaced.empty()) {
    std::string names;
    for (const std::string& n : l.unplaced) {
      if (!names.empty()) names += "; ";
      names += n;
    }
    s << "set label 99 " << gnuplotString("no room to name: " + names)
      << " at screen 0.01, screen 0.02 left font 'sans,9'\n";
  }
  for (std::size_t p = 0; p < l.panels.size(); ++p)
    drawPanel(s, l, p, !front.text().empty(), !chosen.text().empty(),
              zoomed && p == 0 ? &l.panels[1] : nullptr);
  if (zoomed) s << "unset multiplot\n";
  return gnuplotSvg(s);
}

}  // namespace dynid
