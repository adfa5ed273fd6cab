#include "analysis/monitor/feeds.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(StreamedSamples, HeadersAndRowsAreCheckedWithTheirLineAndColumn) {
  EXPECT_FALSE(parseSampleHeader("t,q1,q2,dq1,dq2,tau1,tau2", 2, "<stdin>"));
  EXPECT_TRUE(parseSampleHeader("t,q1,q2,dq1,dq2,ddq1,ddq2,tau1,tau2\r", 2, "<stdin>"));
  try {
    parseSampleHeader("t,q1,q2,q3,dq1,dq2,dq3,tau1,tau2,tau3", 2, "<stdin>");
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("2-joint"), std::string::npos) << e.what();
  }
  double t = 0;
  Eigen::VectorXd q, dq, ddq, tau;
  parseSampleLine("0.5, 1,2, 3,4, 5,6", 2, false, "<stdin>", 3, t, q, dq, ddq, tau);
  EXPECT_EQ(t, 0.5);
  EXPECT_EQ(tau[1], 6.0);
  for (const std::string bad :
       {"0.5,1,2,3,4,5", "0.5,1,nan,3,4,5,6", "0.5,1,2,3,4,5,x", "0.5,1,2,3,4,5,1e999"}) {
    try {
      parseSampleLine(bad, 2, false, "<stdin>", 7, t, q, dq, ddq, tau);
      FAIL() << bad;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), 7) << bad;
      EXPECT_EQ(e.file(), "<stdin>");
    }
  }
}

}  // namespace
}  // namespace dynid
