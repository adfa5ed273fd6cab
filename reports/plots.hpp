// Figures for the reports, drawn by gnuplot as SVG (inlined in the HTML report, written beside the
// Markdown one). A missing or failing gnuplot degrades to no figures and a warning, never an error.
#pragma once

#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "analysis/demo.hpp"

namespace dynid {

struct Figure {
  std::string name;     // file stem, e.g. "gc_error_iterations"
  std::string caption;  // what it shows and what to conclude
  std::string svg;      // the SVG document
};

/// Runs gnuplot (the DYNID_GNUPLOT environment variable, else `gnuplot` on the PATH) on `script`,
/// which must set an svg terminal and plot inline data; the SVG it prints, or nullopt.
std::optional<std::string> gnuplotSvg(const std::string& script);

/// Appends one row of a gnuplot inline data block to `out`: the values with 9 significant digits
/// (printf's %.9g, what an ostream of precision 9 writes), space-separated, then a newline. For
/// figures of thousands of points: no stream formatting per number.
void appendPlotRow(std::string& out, std::initializer_list<double> values);

/// Runs every `draws` function (each builds one figure, typically ending in gnuplotSvg) at once,
/// on threads of its own, and returns their results in order: each gnuplot is a process, so a
/// report's figures take about the time of the slowest, not of all in turn. The functions must
/// only read shared data. An exception from one is rethrown after all have finished.
std::vector<std::optional<std::string>> drawConcurrently(
    const std::vector<std::function<std::optional<std::string>()>>& draws);

/// The demo's figures: the searches' GC error and parameter errors against iteration (the paper's
/// Figs. 2 and 5), and every method's base-parameter and GC errors. Empty, with `warning` set,
/// when gnuplot is unavailable.
std::vector<Figure> demoFigures(const DemoResult& result, std::string* warning);

}  // namespace dynid
