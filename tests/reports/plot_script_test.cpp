#include "reports/plot_script.hpp"

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace dynid {
namespace {

using Draw = std::function<std::optional<std::string>()>;

TEST(PlotRows, WriteWhatAStreamOfPrecisionNineWrites) {
  // The figures' data were written by an ostream of precision 9; to_chars must give the same bytes.
  const double values[] = {0.0,
                           -0.0,
                           1.0,
                           -2.5,
                           0.1,
                           1e-7,
                           123456789.0,
                           1234567890123.0,
                           -3.14159265358979,
                           1e300,
                           -4.9e-324,
                           std::nan(""),
                           std::numeric_limits<double>::infinity()};
  for (double x : values) {
    std::ostringstream expected;
    expected.precision(9);
    expected << x << " " << -x << "\n";
    PlotRows row;
    row.append({x, -x});
    EXPECT_EQ(row.text(), expected.str()) << x;
  }
  PlotRows rows;
  rows.append({1.0});
  rows.append({0.5, 2.0, 3.0});
  rows.append("a \"b\"\nEOD", {4.0});  // a label is one quoted column, on its own line
  EXPECT_EQ(rows.text(), "1\n0.5 2 3\n\"a 'b' EOD\" 4\n");
}

/// Reads a gnuplotString as gnuplot does: single-quoted strings (no quote inside) joined by
/// ."'". (a quote). Returns the text, or nothing when the token is anything else (a string that
/// ends early, an operator or a name: gnuplot code).
std::optional<std::string> readPlotText(const std::string& token) {
  const std::string join = ".\"'\".";
  std::string text;
  std::size_t i = 0;
  while (true) {
    if (i >= token.size() || token[i] != '\'') return std::nullopt;
    const std::size_t end = token.find('\'', i + 1);
    if (end == std::string::npos) return std::nullopt;  // never closed
    text += token.substr(i + 1, end - i - 1);
    i = end + 1;
    if (i == token.size()) return text;
    if (token.compare(i, join.size(), join) != 0) return std::nullopt;
    text += '\'';
    i += join.size();
  }
}

TEST(GnuplotString, IsOneClosedLiteralWhateverTheText) {
  EXPECT_EQ(gnuplotString("joint 1").quoted(), "'joint 1'");
  EXPECT_EQ(gnuplotString("o'brien").quoted(), "'o'.\"'\".'brien'");
  EXPECT_EQ(gnuplotString("'").quoted(), "''.\"'\".''");
  EXPECT_EQ(gnuplotString("a\nb\r\tc").quoted(), "'a b  c'");  // a newline would end the command
  EXPECT_EQ(gnuplotString("x_1^2 {a} @b &c ~d \\e").quoted(),
            "'x\\_1\\^2 \\{a\\} \\@b \\&c \\~d \\\\e'");  // shown as typed, not as markup
  EXPECT_EQ(gnuplotString("caf\xc3\xa9").quoted(), "'caf\xc3\xa9'");  // UTF-8 kept
  EXPECT_EQ(gnuplotString("bad\xff\xc3x").quoted(), "'bad??x'");      // not UTF-8: '?'
  EXPECT_EQ(gnuplotString(std::string(1000, 'x')).quoted(), "'" + std::string(200, 'x') + "...'");
  EXPECT_EQ(gnuplotDataString("say \"hi\"").quoted(), "\"say 'hi'\"");
  for (const std::string name : {"'.system('touch x').'", "''''", "'\n!touch x\n'", "`touch x`"}) {
    const auto text = readPlotText(gnuplotString(name).quoted());
    ASSERT_TRUE(text.has_value()) << name;
    std::string shown = name;  // what the figure shows: control characters as spaces
    std::replace(shown.begin(), shown.end(), '\n', ' ');
    EXPECT_EQ(*text, shown) << name;
  }
}

/// Names that would run `touch <marker>` if they reached gnuplot as code, in every form the
/// hardening review tried (quotes, newlines, backquotes, macros, system(), long, not UTF-8).
std::vector<std::string> hostileNames(const std::string& marker) {
  return {"'.system('touch " + marker + "').'",
          "\".system(\"touch " + marker + "\").\"",
          "x'\nsystem('touch " + marker + "')\n#",
          "`touch " + marker + "`",
          "$(touch " + marker + ")",
          "a; touch " + marker,
          "@x @y {\\\\} \\' ''",
          "line1\nEOD\n!touch " + marker + "\n",
          std::string(5000, '\'') + "system('touch " + marker + "')",
          "\xff\xfe'\xc0\x80 system('touch " + marker + "')"};
}

TEST(GnuplotSvg, HostileNamesRunNothingAndKeepTheFigure) {
  if (std::system("gnuplot --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  const std::string marker = ::testing::TempDir() + "dynid_plot_marker";
  std::remove(marker.c_str());
  for (const std::string& name : hostileNames(marker)) {
    PlotScript s;
    PlotRows rows;
    rows.append(name, {1.0, 2.0});
    rows.append("second", {2.0, 3.0});
    s << "set terminal svg\nset title " << gnuplotString(name) << "\nset xlabel "
      << gnuplotString(name) << "\n$d << EOD\n"
      << rows << "EOD\nplot $d using 2:3:xtic(1) title " << gnuplotString(name) << "\n";
    const auto svg = gnuplotSvg(s);
    EXPECT_TRUE(svg.has_value()) << name;
    EXPECT_NE(::access(marker.c_str(), F_OK), 0) << "a command ran for: " << name;
  }
}

TEST(GnuplotSvg, AScriptLargerThanAPipeAndALargeFigureBothPass) {
  if (std::system("gnuplot --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  // 200,000 points: the script (~3 MB) and the SVG both overflow a pipe's buffer, so writing
  // the one and reading the other must interleave.
  PlotScript s;
  PlotRows rows;
  for (int k = 0; k < 200000; ++k) rows.append({k * 1e-3, std::sin(k * 1e-3)});
  s << "set terminal svg\n$d << EOD\n" << rows << "EOD\nplot $d using 1:2 with lines\n";
  const auto svg = gnuplotSvg(s);
  ASSERT_TRUE(svg.has_value());
  EXPECT_GT(svg->size(), std::size_t{1} << 16);
}

TEST(GnuplotSvg, AProgramThatReadsNothingGivesNoFigureAndNoSignal) {
  // `true` exits without reading: writing the script then fails (EPIPE), which must neither kill
  // the process with SIGPIPE nor hang.
  PlotScript s;
  PlotRows rows;
  for (int k = 0; k < 100000; ++k) rows.append({1.0 * k});
  s << "set terminal svg\n$d << EOD\n" << rows << "EOD\nplot $d\n";
  ::setenv("DYNID_GNUPLOT", "true", 1);
  EXPECT_FALSE(gnuplotSvg(s).has_value());
  ::unsetenv("DYNID_GNUPLOT");
}

TEST(DrawConcurrently, ReturnsEachResultInItsPlace) {
  const std::vector<std::optional<std::string>> out = drawConcurrently(
      {[] { return std::optional<std::string>("a"); }, [] { return std::optional<std::string>(); },
       [] { return std::optional<std::string>("c"); }});
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0], "a");
  EXPECT_FALSE(out[1].has_value());
  EXPECT_EQ(out[2], "c");
  EXPECT_TRUE(drawConcurrently({}).empty());
}

TEST(DrawConcurrently, RunsTheDrawsAtTheSameTime) {
  // Each draw waits until all three have started: drawn one after another, none would see the
  // others (and each gives up after 20 s, so a sequential implementation fails, never hangs).
  std::atomic<int> started{0};
  const Draw draw = [&]() -> std::optional<std::string> {
    ++started;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (started.load() < 3)
      if (std::chrono::steady_clock::now() > deadline)
        return std::nullopt;
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return "together";
  };
  for (const auto& svg : drawConcurrently({draw, draw, draw})) EXPECT_EQ(svg, "together");
}

TEST(DrawConcurrently, RethrowsAfterEveryDrawHasFinished) {
  std::atomic<int> finished{0};
  const Draw slow = [&]() -> std::optional<std::string> {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ++finished;
    return "slow";
  };
  const Draw failing = []() -> std::optional<std::string> {
    throw std::runtime_error("figure failed");
  };
  EXPECT_THROW(drawConcurrently({failing, slow, slow}), std::runtime_error);
  EXPECT_EQ(finished.load(), 2);  // no thread left running on the caller's data
}

TEST(GnuplotSvg, ConcurrentGnuplotsEachReturnTheirOwnFigure) {
  if (std::system("gnuplot --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  std::vector<Draw> draws;
  for (int k = 0; k < 4; ++k)
    draws.push_back([k] {
      PlotScript s;
      s << "set terminal svg\nset title 'figure " << k << "'\nplot x*" << k << "\n";
      return gnuplotSvg(s);
    });
  const auto svgs = drawConcurrently(draws);
  for (int k = 0; k < 4; ++k) {
    ASSERT_TRUE(svgs[static_cast<std::size_t>(k)].has_value()) << k;
    EXPECT_NE(svgs[static_cast<std::size_t>(k)]->find("figure " + std::to_string(k)),
              std::string::npos)
        << k;
  }
}

TEST(GnuplotSvg, AFailingProgramGivesNoFigure) {
  PlotScript s;
  s << "set terminal svg\nplot x\n";
  ::setenv("DYNID_GNUPLOT", "false", 1);
  EXPECT_FALSE(gnuplotSvg(s).has_value());
  ::setenv("DYNID_GNUPLOT", "/nonexistent/gnuplot", 1);
  EXPECT_FALSE(gnuplotSvg(s).has_value());
  ::unsetenv("DYNID_GNUPLOT");
}

TEST(NoShell, OnlyTheListedSpawnsStartProgramsAndNothingBuildsACommandLine) {
  // No input string can become a command: figures start gnuplot with posix_spawnp (no shell) and
  // give it a PlotScript, batch starts its own workers with posix_spawn, and rerun this
  // executable with a document's recorded arguments as argv (never through a shell); no other
  // code starts a program. A new call of any of these fails here until it is reviewed and listed.
  namespace fs = std::filesystem;
  const std::vector<std::string> forbidden = {
      "popen(",  "system(", "execl(", "execlp(", "execle(",      "execv(",
      "execvp(", "execve(", "fork(",  "/bin/sh", "posix_spawn(", "posix_spawnp("};
  const std::vector<std::pair<std::string, std::string>> allowed = {
      {"reports/plot_script.cpp", "posix_spawnp("},
      {"cli/batch_workers.cpp", "posix_spawn("},
      {"cli/command_rerun.cpp", "posix_spawn("}};
  int files = 0;
  for (const char* dir :
       {"core", "identifiability", "search", "analysis", "data", "reports", "cli", "python"}) {
    for (const auto& entry :
         fs::recursive_directory_iterator(std::string(DYNID_SOURCE_DIR) + "/" + dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext != ".cpp" && ext != ".hpp") continue;
      ++files;
      const std::string relative = fs::relative(entry.path(), DYNID_SOURCE_DIR).string();
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        const std::size_t code = line.find_first_not_of(" \t");
        if (code != std::string::npos && line.compare(code, 2, "//") == 0) continue;  // a comment
        for (const std::string& call : forbidden) {
          std::size_t at = line.find(call);
          // "posix_spawn(" inside "::posix_spawnp(" is not a match; a name ending in it is not one.
          if (at == std::string::npos) continue;
          if (at > 0 &&
              (std::isalnum(static_cast<unsigned char>(line[at - 1])) || line[at - 1] == '_'))
            continue;
          const bool listed = std::find(allowed.begin(), allowed.end(),
                                        std::make_pair(relative, call)) != allowed.end();
          EXPECT_TRUE(listed) << relative << ":" << number << " calls " << call << ": " << line;
        }
      }
    }
  }
  EXPECT_GT(files, 100);  // the tree was found
}

}  // namespace
}  // namespace dynid
