// Gnuplot scripts and the runner that draws them. No input string ever becomes gnuplot code: a
// script is a PlotScript, which takes only string literals (code written here), numbers, numeric
// data rows and PlotText, the one escaped form of a string (gnuplotString); gnuplot is started
// without a shell and reads the script on its standard input (no temporary file).
// tests/reports/plot_script_test.cpp runs hostile names through it; tests/fuzz/fuzz_plot_text.cpp
// checks the escaping with an injection oracle.
#pragma once

#include <cstddef>
#include <functional>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace dynid {

/// A string as one gnuplot text expression (a title, a label, a key entry): single-quoted pieces,
/// each quote of the text a double-quoted "'" between them ('o'."'".'brien'; nothing is expanded
/// in either: a double-quoted string holding only a quote has no `command` to run), the
/// enhanced-text characters (^ _ @ & ~ { } \) shown as themselves, control characters
/// (newlines included) as spaces, bytes that are not UTF-8 as '?', and at most 200 bytes of the
/// text (then "..."). Inside single quotes gnuplot expands nothing (no `command`, no @macro).
class PlotText {
 public:
  const std::string& quoted() const { return quoted_; }

 private:
  friend PlotText gnuplotString(std::string_view text);
  friend PlotText gnuplotDataString(std::string_view text);
  explicit PlotText(std::string quoted) : quoted_(std::move(quoted)) {}
  std::string quoted_;
};
PlotText gnuplotString(std::string_view text);
/// A string as one double-quoted column of an inline data block (an xtic label): as
/// gnuplotString's text, with double quotes shown as single ones.
PlotText gnuplotDataString(std::string_view text);

/// Rows of an inline data block: numbers, and optionally a leading label column.
class PlotRows {
 public:
  /// One row: the values with 9 significant digits (printf's %.9g), space-separated. For figures
  /// of thousands of points: no stream formatting per number.
  void append(std::initializer_list<double> values);
  void append(const std::vector<double>& values);
  /// One row whose first column is `label` (gnuplotDataString), then the values.
  void append(std::string_view label, std::initializer_list<double> values);
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

/// A gnuplot script: code from string literals, numbers, data rows and escaped text only (a
/// std::string does not compile here: it must go through gnuplotString).
class PlotScript {
 public:
  template <std::size_t N>
  PlotScript& operator<<(const char (&code)[N]) {
    out_ << code;
    return *this;
  }
  PlotScript& operator<<(int x);
  PlotScript& operator<<(long x);
  PlotScript& operator<<(unsigned long x);
  PlotScript& operator<<(double x);
  PlotScript& operator<<(const PlotText& text);
  PlotScript& operator<<(const PlotRows& rows);
  /// Significant digits of the numbers written from here on (the stream's, 6 by default).
  void precision(int digits) { out_.precision(digits); }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

/// Runs gnuplot (the DYNID_GNUPLOT environment variable, else `gnuplot` on the PATH; started
/// without a shell, the script on its standard input) on `script`, which must set an svg terminal
/// and plot inline data; the SVG it prints, or nullopt.
std::optional<std::string> gnuplotSvg(const PlotScript& script);

/// Runs every `draws` function (each builds one figure, typically ending in gnuplotSvg) at once,
/// on threads of its own, and returns their results in order: each gnuplot is a process, so a
/// report's figures take about the time of the slowest, not of all in turn. The functions must
/// only read shared data. An exception from one is rethrown after all have finished.
std::vector<std::optional<std::string>> drawConcurrently(
    const std::vector<std::function<std::optional<std::string>()>>& draws);

}  // namespace dynid
