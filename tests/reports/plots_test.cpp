#include "reports/plots.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace dynid {
namespace {

using Draw = std::function<std::optional<std::string>()>;

TEST(AppendPlotRow, WritesWhatAStreamOfPrecisionNineWrites) {
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
    std::string row;
    appendPlotRow(row, {x, -x});
    EXPECT_EQ(row, expected.str()) << x;
  }
  std::string rows = "$d << EOD\n";
  appendPlotRow(rows, {1.0});
  appendPlotRow(rows, {0.5, 2.0, 3.0});
  EXPECT_EQ(rows, "$d << EOD\n1\n0.5 2 3\n");
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
      return gnuplotSvg("set terminal svg\nset title 'figure " + std::to_string(k) + "'\nplot x*" +
                        std::to_string(k) + "\n");
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
  ::setenv("DYNID_GNUPLOT", "false", 1);
  EXPECT_FALSE(gnuplotSvg("set terminal svg\nplot x\n").has_value());
  ::unsetenv("DYNID_GNUPLOT");
}

}  // namespace
}  // namespace dynid
