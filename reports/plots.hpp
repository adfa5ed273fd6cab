// The demo's figures, drawn by gnuplot as SVG (inlined in the HTML report, written beside the
// Markdown one) through reports/plot_script.hpp. A missing or failing gnuplot degrades to no
// figures and a warning, never an error.
#pragma once

#include <string>
#include <vector>

#include "analysis/studies/demo.hpp"
#include "reports/plot_script.hpp"

namespace dynid {

struct Figure {
  std::string name;     // file stem, e.g. "gc_error_iterations"
  std::string caption;  // what it shows and what to conclude
  std::string svg;      // the SVG document
};

/// The demo's figures: the searches' GC error and parameter errors against iteration (the paper's
/// Figs. 2 and 5), and every method's base-parameter and GC errors. Empty, with `warning` set,
/// when gnuplot is unavailable.
std::vector<Figure> demoFigures(const DemoResult& result, std::string* warning);

}  // namespace dynid
