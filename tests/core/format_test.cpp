#include "core/format.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

namespace dynid {
namespace {

TEST(FormatNumber, SignificantDigitsAsPrintfG) {
  EXPECT_EQ(formatNumber(0.0123456, 3), "0.0123");
  EXPECT_EQ(formatNumber(1234567.0, 3), "1.23e+06");
  EXPECT_EQ(formatNumber(2.0, 4), "2");
  EXPECT_EQ(formatNumber(-0.5, 6), "-0.5");
  EXPECT_EQ(formatNumber(1.0 / 3.0, 17), "0.33333333333333331");
}

TEST(FormatNumber, ZeroDigitsIsTheShortestTextThatReadsBackExactly) {
  EXPECT_EQ(formatNumber(0.1), "0.1");
  EXPECT_EQ(formatNumber(1e300), "1e+300");
  EXPECT_EQ(formatNumber(1000000.0), "1e+06");  // the shorter of the two exact forms
  EXPECT_EQ(formatNumber(123456.0), "123456");
  for (double x : {1.0 / 3.0, 6.02214076e23, -2.5e-308, 4.9e-324}) {
    const std::string text = formatNumber(x);
    double back = 0.0;
    std::from_chars(text.data(), text.data() + text.size(), back);
    EXPECT_EQ(back, x) << text;
  }
}

TEST(FormatNumber, NonFiniteValuesReadAsTheCallerAsks) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(formatNumber(inf), "inf");
  EXPECT_EQ(formatNumber(-inf, 3), "-inf");
  EXPECT_EQ(formatNumber(std::nan(""), 4), "nan");
  EXPECT_EQ(formatNumber(inf, 3, "n/a"), "n/a");
  EXPECT_EQ(formatNumber(2.5, 3, "n/a"), "2.5");  // a finite value ignores the substitute
}

}  // namespace
TEST(ProgressText, ShareDoneAndTheTimeLeftExtrapolated) {
  EXPECT_EQ(progressText(0.0, 3.0), "0 %");  // nothing done: no estimate yet
  EXPECT_EQ(progressText(0.25, 10.0), "25 %, about 30 s left");
  EXPECT_EQ(progressText(0.5, 65.0), "50 %, about 1 min 5 s left");
  EXPECT_EQ(progressText(0.999, 1.0), "99 %, about 0 s left");  // floored, never "100 %" early
  EXPECT_EQ(progressText(1.0, 10.0), "100 %");
  EXPECT_EQ(progressText(1.7, 10.0), "100 %");  // a budget overrun is clamped
  EXPECT_EQ(progressText(std::nan(""), 10.0), "0 %");
}

}  // namespace dynid
