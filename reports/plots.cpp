#include "reports/plots.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <sstream>

#include "core/format.hpp"

extern char** environ;

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
            "set xtics rotate by -30\nunset key\n$d << EOD\n";
    header(gc, "GC error on the training and a held-out path (paper Fig. 3)", "", "GC error");
    gc << "set style data histograms\nset style histogram clustered\nset style fill solid 0.7\n"
          "set xtics rotate by -30\n$d << EOD\n";
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

namespace {

constexpr std::size_t kMaxPlotText = 200;  // bytes of a title or label kept

/// The length of the UTF-8 sequence starting at text[i], or 0 when it is not a valid one.
std::size_t utf8Length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  unsigned min = 0;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2, min = 0x80;
  else if (c >= 0xE0 && c <= 0xEF)
    n = 3, min = 0x800;
  else if (c >= 0xF0 && c <= 0xF4)
    n = 4, min = 0x10000;
  else
    return 0;
  if (i + n > text.size()) return 0;
  unsigned code = c & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

/// The text between the quotes: `quote` kept (the caller splits there) or replaced (data: '"'
/// shown as '\''),
/// enhanced-text characters escaped, control characters as spaces, invalid UTF-8 as '?'.
std::string plotTextBody(std::string_view text, char quote) {
  std::string out;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (kept >= kMaxPlotText) {
      out += "...";
      break;
    }
    const std::size_t n = utf8Length(text, i);
    if (n == 0) {
      out += '?';
      ++i, ++kept;
      continue;
    }
    if (n > 1) {
      out.append(text.substr(i, n));
      i += n, kept += n;
      continue;
    }
    const char c = text[i];
    ++i, ++kept;
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      out += ' ';
    } else if (c == '"' && quote == '"') {
      out += '\'';
    } else {
      if (std::string_view("^_@&~{}\\").find(c) != std::string_view::npos) out += '\\';
      out += c;
    }
  }
  return out;
}

/// Writes all of `script` to gnuplot's stdin while reading its stdout (either may fill its pipe
/// first); at most kMaxSvgBytes are read. False on an I/O error or an oversized figure.
constexpr std::size_t kMaxSvgBytes = std::size_t{256} << 20;
bool exchange(int in, int out, const std::string& script, std::string& svg) {
  std::size_t written = 0;
  if (script.empty()) ::close(in), in = -1;
  while (out >= 0) {
    pollfd fds[2] = {{out, POLLIN, 0}, {in, POLLOUT, 0}};
    const int ready = ::poll(fds, in >= 0 ? 2 : 1, -1);
    if (ready < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (in >= 0 && (fds[1].revents & (POLLOUT | POLLERR | POLLHUP)) != 0) {
      const ssize_t n = ::write(in, script.data() + written, script.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      if ((n < 0 && errno != EINTR && errno != EAGAIN) || written == script.size())
        ::close(in), in = -1;  // done, or gnuplot stopped reading (EPIPE)
    }
    if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      char buffer[1 << 16];
      const ssize_t n = ::read(out, buffer, sizeof(buffer));
      if (n > 0) {
        svg.append(buffer, static_cast<std::size_t>(n));
        if (svg.size() > kMaxSvgBytes) break;
      } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
        break;
      }
    }
  }
  if (in >= 0) ::close(in);
  if (out >= 0) ::close(out);
  return svg.size() <= kMaxSvgBytes;
}

}  // namespace

PlotText gnuplotString(std::string_view text) {
  // Single-quoted pieces joined by a double-quoted quote ('o'."'".'brien'): gnuplot reads a
  // doubled quote ('') at a string's start as an empty string, so quotes are never doubled.
  const std::string body = plotTextBody(text, '\'');
  std::string quoted(1, '\'');
  for (const char c : body)
    if (c == '\'')
      quoted.append("'.\"'\".'");
    else
      quoted.append(1, c);
  quoted.append(1, '\'');
  return PlotText(std::move(quoted));
}

PlotText gnuplotDataString(std::string_view text) {
  std::string quoted(1, '"');
  quoted.append(plotTextBody(text, '"')).append(1, '"');
  return PlotText(std::move(quoted));
}

void PlotRows::append(std::initializer_list<double> values) { append(std::vector<double>(values)); }

void PlotRows::append(const std::vector<double>& values) {
  std::array<char, 32> buffer;
  bool first = true;
  for (double x : values) {
    if (!first) text_ += ' ';
    first = false;
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x,
                                      std::chars_format::general, 9);
    text_.append(buffer.data(), result.ptr);
  }
  text_ += '\n';
}

void PlotRows::append(std::string_view label, std::initializer_list<double> values) {
  text_ += gnuplotDataString(label).quoted();
  if (values.size() > 0) text_ += ' ';
  append(values);
}

PlotScript& PlotScript::operator<<(int x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(long x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(unsigned long x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(double x) {
  out_ << x;
  return *this;
}
PlotScript& PlotScript::operator<<(const PlotText& text) {
  out_ << text.quoted();
  return *this;
}
PlotScript& PlotScript::operator<<(const PlotRows& rows) {
  out_ << rows.text();
  return *this;
}

std::optional<std::string> gnuplotSvg(const PlotScript& plot) {
  const char* configured = std::getenv("DYNID_GNUPLOT");
  std::string program = configured != nullptr && *configured != '\0' ? configured : "gnuplot";
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0) return std::nullopt;
  if (::pipe2(out, O_CLOEXEC) != 0) {
    ::close(in[0]), ::close(in[1]);
    return std::nullopt;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  char* argv[] = {program.data(), nullptr};
  pid_t pid = -1;
  // posix_spawnp: the program's name is looked up on the PATH, its path used as it is; no shell.
  const int spawned = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(in[0]), ::close(out[1]);
  if (spawned != 0) {
    ::close(in[1]), ::close(out[0]);
    return std::nullopt;
  }
  // A gnuplot that stops reading must not kill this process with SIGPIPE: blocked on this
  // thread while writing, and a pending one taken back before unblocking.
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
  ::fcntl(in[1], F_SETFL, O_NONBLOCK);
  std::string svg;
  const bool whole = exchange(in[1], out[0], plot.str(), svg);
  const timespec no_wait{0, 0};
  while (sigtimedwait(&pipe_signal, nullptr, &no_wait) > 0) {
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (!whole) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!whole || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  if (svg.find("<svg") == std::string::npos || svg.find("</svg>") == std::string::npos)
    return std::nullopt;
  return svg;
}

std::vector<std::optional<std::string>> drawConcurrently(
    const std::vector<std::function<std::optional<std::string>()>>& draws) {
  std::vector<std::future<std::optional<std::string>>> running;
  running.reserve(draws.size());
  for (const auto& draw : draws) running.push_back(std::async(std::launch::async, draw));
  std::vector<std::optional<std::string>> out;
  std::exception_ptr failure;
  for (auto& r : running) {  // every one waited for before any exception leaves
    try {
      out.push_back(r.get());
    } catch (...) {
      if (!failure) failure = std::current_exception();
      out.emplace_back();
    }
  }
  if (failure) std::rethrow_exception(failure);
  return out;
}

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
