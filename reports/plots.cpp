#include "reports/plots.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "core/format.hpp"

namespace dynid {

namespace {

std::string g3(double x) { return formatNumber(x, 3, "n/a"); }

/// Gnuplot's opening lines: an SVG terminal and a plain style.
void header(PlotScript& s, std::string_view title, std::string_view xlabel,
            std::string_view ylabel) {
  s << "set terminal svg size 720,420 font 'sans,12' background rgb 'white'\nset title "
    << gnuplotString(title) << "\nset xlabel " << gnuplotString(xlabel) << "\nset ylabel "
    << gnuplotString(ylabel)
    << "\nset grid\nset key top right\nset logscale y\nset format y '10^{%L}'\n";
}

const MethodMetrics* find(const DemoResult& result, Method method) {
  for (const MethodMetrics& m : result.methods)
    if (m.key == methodName(method)) return &m;
  return nullptr;
}

/// Adds one figure (name, caption, gnuplot script); false when gnuplot made none.
using AddFigure = std::function<bool(const std::string&, const std::string&, const PlotScript&)>;

/// Figs. 2 and 5: the searches' course.
void addSearchCourse(const DemoResult& result, const AddFigure& add) {
  if (!result.searches.empty()) {
    PlotScript gc, errors;
    // x counts a search's rounds and generations in order, so the hybrid's NLO rounds continue
    // after its GA generations instead of starting again at 1.
    const std::string xlabel = "round (NLO) or generation (GA); hybrid: generations, then rounds";
    header(gc, "GC error of the best candidate (paper Fig. 2)", xlabel, "training GC error");
    header(errors, "Parameter errors during the searches (paper Fig. 5)", xlabel, "error");
    // Nine entries: below the plot in three rows, on a taller canvas, clear of the lines.
    errors << "set terminal svg size 720,500 font 'sans,12' background rgb 'white'\n"
              "set key below horizontal maxcols 3\n";
    // One data block per search, $s0, $s1, ...: named by index, never by a string.
    for (std::size_t s = 0; s < result.searches.size(); ++s) {
      const DemoSearchTrace& t = result.searches[s];
      gc << "$s" << s << " << EOD\n";
      errors << "$s" << s << " << EOD\n";
      PlotRows gc_rows, error_rows;
      for (std::size_t i = 0; i < t.history.size(); ++i) {
        const HistoryEntry& h = t.history[i];
        gc_rows.append({static_cast<double>(i + 1), h.best_gc});
        error_rows.append({static_cast<double>(i + 1), h.best_parameter_error,
                           h.min_parameter_error,
                           i < t.base_errors.size() ? t.base_errors[i] : NAN});
      }
      gc << gc_rows << "EOD\n";
      errors << error_rows << "EOD\n";
    }
    for (std::size_t s = 0; s < result.searches.size(); ++s) {
      const std::string& method = result.searches[s].method;
      if (s == 0)
        gc << "plot ";
      else
        gc << ", ";
      gc << "$s" << s << " using 1:2 with linespoints title " << gnuplotString(method);
      // Short titles (the caption says what each is), three to a row below the plot.
      if (s == 0)
        errors << "plot ";
      else
        errors << ", ";
      errors << "$s" << s << " using 1:2 with lines title " << gnuplotString(method + " best-GC")
             << ", $s" << s << " using 1:3 with lines dt 2 title "
             << gnuplotString(method + " lowest") << ", $s" << s
             << " using 1:4 with lines dt 3 lw 2 title "
             << gnuplotString(method + " best-GC, base");
    }
    gc << "\n";
    errors << "\n";
    std::string gc_caption =
        "The training GC error of each search's best candidate at every round (NLO) or generation "
        "(GA). Every search cuts the error by orders of magnitude:";
    for (const DemoSearchTrace& t : result.searches)
      if (!t.history.empty())
        gc_caption += " " + t.method + " " + g3(t.history.front().best_gc) + " to " +
                      g3(t.history.back().best_gc) + ";";
    gc_caption.back() = '.';
    add("gc_error_iterations", gc_caption, gc);
    std::string error_caption =
        "The 7-parameter error, eq. (1), of the best-GC candidate (solid) and the lowest one in "
        "the population (dashed), and the best-GC candidate's base-parameter error (dotted), the "
        "same candidate measured in the coordinates the data determine. Over every evaluated "
        "candidate, the correlation of log GC error with log 7-parameter error is";
    double strongest = -1.0;
    for (const DemoSearchTrace& t : result.searches) {
      error_caption += " " + t.method + " r = " + g3(t.pearson_log) + " (Spearman " +
                       g3(t.spearman) + ", " + std::to_string(t.candidates) + " candidates);";
      if (std::isfinite(t.pearson_log)) strongest = std::max(strongest, t.pearson_log);
    }
    error_caption.back() = '.';
    error_caption += strongest < 0.5
                         ? " So a lower prediction error does not mean lower parameter errors "
                           "here, the paper's finding: the GC error sees the base parameters only."
                         : " Here the two errors fall together.";
    add("parameter_error_iterations", error_caption, errors);
  }
}

/// The correlation behind Fig. 5: every evaluated candidate's two errors.
void addCandidateScatter(const DemoResult& result, const AddFigure& add) {
  if (!result.searches.empty()) {
    PlotScript scatter;
    header(scatter, "GC error against 7-parameter error, every evaluated candidate",
           "7-parameter error, eq. (1)", "training GC error");
    scatter << "set logscale x\nset format x '10^{%L}'\n";
    for (std::size_t s = 0; s < result.searches.size(); ++s) {
      PlotRows rows;
      for (const auto& [gc, error] : result.searches[s].evaluated) rows.append({error, gc});
      scatter << "$s" << s << " << EOD\n" << rows << "EOD\n";
    }
    for (std::size_t s = 0; s < result.searches.size(); ++s) {
      if (s == 0)
        scatter << "plot ";
      else
        scatter << ", ";
      scatter << "$s" << s << " using 1:2 with points pt 7 ps 0.3 title "
              << gnuplotString(result.searches[s].method);
    }
    scatter << "\n";
    add("gc_against_parameter_error",
        "Each point is one candidate a search evaluated (at most 2000 per search shown): its "
        "7-parameter error against its GC error. Were the GC error a guide to the parameters, the "
        "points would fall along a rising line towards the origin; the correlations are in "
        "Figure 2's caption and summary.json.",
        scatter);
  }
}

/// Every method, in base coordinates and in prediction.
void addMethodComparison(const DemoResult& result, const AddFigure& add) {
  if (!result.methods.empty()) {
    PlotScript base, gc;
    header(base, "Base-parameter error by method", "", "RMS relative error of the base parameters");
    base << "set style data histograms\nset style fill solid 0.7\nset boxwidth 0.7\n"
            "set xtics rotate by -30 noenhanced\nunset key\n$d << EOD\n";
    header(gc, "GC error on the training and a held-out path (paper Fig. 3)", "", "GC error");
    gc << "set style data histograms\nset style histogram clustered\nset style fill solid 0.7\n"
          "set xtics rotate by -30 noenhanced\n$d << EOD\n";
    PlotRows base_rows, gc_rows;
    gc_rows.append("initial_guess", {result.initial_gc_train, result.initial_gc_test});
    for (const MethodMetrics& m : result.methods) {
      base_rows.append(m.key, {m.base_param_error});
      gc_rows.append(m.key, {m.gc_error_train, m.gc_error_test});
    }
    base << base_rows << "EOD\nplot $d using 2:xtic(1)\n";
    gc << gc_rows << "EOD\nplot $d using 2:xtic(1) title 'training', '' using 3 title 'held out'\n";
    std::string base_caption =
        "Each method's error in the coordinates the data determine, the base parameters.";
    const MethodMetrics* ols = find(result, Method::kOls);
    const MethodMetrics* refined = find(result, Method::kNloRefined);
    const MethodMetrics* nlo = find(result, Method::kNlo);
    if (ols != nullptr && nlo != nullptr && refined != nullptr)
      base_caption += " Least squares (" + g3(ols->base_param_error) + ") and refined searches (" +
                      g3(refined->base_param_error) + ") reach them; the searches alone stop at " +
                      g3(nlo->base_param_error) + " (NLO).";
    add("base_parameter_error", base_caption, base);
    add("gc_error_methods",
        "The GC error of the initial guess and of each estimate on the training data and on a "
        "held-out control path (other frequencies, amplitude and phase). Every estimate predicts "
        "the new path better than the initial guess (" +
            g3(result.initial_gc_test) +
            "); those whose base parameters are right predict it as well as the training one.",
        gc);
  }
}

/// What explains the figures: the GC error's blind directions.
void addNullSpace(const DemoResult& result, const AddFigure& add) {
  const NullSpaces& ns = result.null_spaces;
  if (!ns.gc_singular_values.empty()) {
    PlotScript sv;
    header(sv, "Singular values of the GC residuals' Jacobian at the truth", "index",
           "singular value (unit columns)");
    sv << "set yrange [1e-18:*]\n";
    const int rank = ns.standard - ns.gc_near_null;
    sv << "set arrow from " << rank + 0.5 << ", graph 0 to " << rank + 0.5
       << ", graph 1 nohead lc rgb '#228833' lw 2\nset label 'base parameters: "
       << ns.standard - ns.regressor_null << "' at " << rank + 0.5
       << ", graph 0.5 left offset 0.5,0 tc rgb '#228833'\n$d << EOD\n";
    PlotRows rows;
    for (std::size_t k = 0; k < ns.gc_singular_values.size(); ++k)
      // Exact zeros (parameters no rollout depends on) at the plot's floor.
      rows.append({static_cast<double>(k + 1), std::max(ns.gc_singular_values[k], 1e-18)});
    sv << rows
       << "EOD\nplot $d using 1:2 with impulses lw 4 lc rgb '#4477aa' title 'GC Jacobian'\n";
    std::string caption =
        "The singular values of the Jacobian of the GC residuals with respect to the " +
        std::to_string(ns.standard) +
        " standard parameters at the truth, columns scaled to unit norm. The green line is the "
        "number of base parameters, the torques' rank. " +
        std::to_string(ns.gc_near_null) + " singular values are at round-off";
    if (!ns.principal_angles_deg.empty())
      caption +=
          ", and their span meets the regressor's null space at principal angles of at "
          "most " +
          g3(ns.principal_angles_deg.back()) + " degrees";
    caption += ": the GC error sees the base parameters and nothing else.";
    add("gc_jacobian_singular_values", caption, sv);
  }
}

/// Fig. 4: near-truth configurations' held-out GC errors, the estimate's marked.
void addNearTruth(const DemoResult& result, const AddFigure& add) {
  const NearTruth& near = result.near_truth;
  if (!near.gc_errors.empty()) {
    double lo = std::log10(near.estimate_gc), hi = lo;
    for (double g : near.gc_errors)
      if (g > 0.0) lo = std::min(lo, std::log10(g)), hi = std::max(hi, std::log10(g));
    const int bins = 20;
    const double width = std::max((hi - lo) / bins, 1e-12);
    std::vector<int> counts(bins, 0);
    for (double g : near.gc_errors)
      if (g > 0.0) ++counts[std::min(bins - 1, static_cast<int>((std::log10(g) - lo) / width))];
    const double mark = std::log10(near.estimate_gc);
    PlotScript h;
    h << "set terminal svg size 720,420 font 'sans,12' background rgb 'white'\nset title "
      << gnuplotString("Held-out GC errors of configurations within " + g3(100.0 * near.range) +
                       " % of the truth (paper Fig. 4)")
      << "\nset xlabel 'log10 held-out GC error'\n"
         "set ylabel 'configurations'\nset grid\nset key below\nset style fill solid 0.7\n"
         "set boxwidth "
      << 0.9 * width << "\nset yrange [0:*]\n"
      << "set arrow from " << mark << ", graph 0 to " << mark
      << ", graph 1 nohead lc rgb '#228833' lw 3\n"
      << "set label " << gnuplotString(near.estimate + " estimate") << " at " << mark
      << ", graph 0.95 ";
    // The label on the side of the line with room: left of it in the right half of the axis.
    if (mark > 0.5 * (lo + hi))
      h << "right offset -0.5,0";
    else
      h << "offset 0.5,0";
    h << " tc rgb '#228833'\n$d << EOD\n";
    PlotRows rows;
    for (int b = 0; b < bins; ++b) rows.append({lo + (b + 0.5) * width, double(counts[b])});
    h << rows
      << "EOD\nplot $d using 1:2 with boxes lc rgb '#4477aa' title 'near-truth configurations'\n";
    add("near_truth_histogram",
        "The held-out GC errors of " + std::to_string(near.gc_errors.size()) +
            " random configurations whose every parameter is within " + g3(100.0 * near.range) +
            " % of its true value; the green line marks the " + near.estimate + " estimate (" +
            g3(near.estimate_gc) + "). " + g3(near.percentile) +
            " % of the near-truth configurations do as well or better: a search can predict as "
            "well as configurations much closer to the truth.",
        h);
  }
}

}  // namespace

std::vector<Figure> demoFigures(const DemoResult& result, std::string* warning) {
  std::vector<Figure> figures;
  const auto add = [&](const std::string& name, const std::string& caption,
                       const PlotScript& script) {
    if (const auto svg = gnuplotSvg(script)) {
      figures.push_back({name, caption, *svg});
      return true;
    }
    return false;
  };

  addSearchCourse(result, add);
  addCandidateScatter(result, add);
  addMethodComparison(result, add);
  addNullSpace(result, add);
  addNearTruth(result, add);
  if (figures.empty() && warning != nullptr)
    *warning = "gnuplot not available (DYNID_GNUPLOT or gnuplot on the PATH): no figures";
  return figures;
}

}  // namespace dynid
