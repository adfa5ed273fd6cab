// Figures for the reports, drawn by gnuplot as SVG (inlined in the HTML report, written beside the
// Markdown one). A missing or failing gnuplot degrades to no figures and a warning, never an error.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/demo.hpp"

namespace dynid {

/// A number as every report prints it: three significant digits ("%.3g"), "n/a" when not finite.
std::string threeDigits(double x);

struct Figure {
  std::string name;     // file stem, e.g. "gc_error_iterations"
  std::string caption;  // what it shows and what to conclude
  std::string svg;      // the SVG document
};

/// Runs gnuplot (the DYNID_GNUPLOT environment variable, else `gnuplot` on the PATH) on `script`,
/// which must set an svg terminal and plot inline data; the SVG it prints, or nullopt.
std::optional<std::string> gnuplotSvg(const std::string& script);

/// The demo's figures: the searches' GC error and parameter errors against iteration (the paper's
/// Figs. 2 and 5), and every method's base-parameter and GC errors. Empty, with `warning` set,
/// when gnuplot is unavailable.
std::vector<Figure> demoFigures(const DemoResult& result, std::string* warning);

}  // namespace dynid
