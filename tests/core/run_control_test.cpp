#include "core/run_control.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <limits>
#include <string>
#include <vector>

namespace dynid {
namespace {

using Clock = RunControl::Clock;

TEST(RunControl, StopsOnItsFlagOrItsDeadline) {
  RunControl control;
  EXPECT_FALSE(control.stopped());  // neither flag nor deadline: runs to the end
  std::atomic<bool> flag{false};
  control.stop = &flag;
  EXPECT_FALSE(control.stopped());
  flag = true;
  EXPECT_TRUE(control.interrupted());
  EXPECT_FALSE(control.expired());
  EXPECT_TRUE(control.stopped());

  RunControl late;
  late.deadline = Clock::now() - std::chrono::seconds(1);
  EXPECT_TRUE(late.expired());
  EXPECT_FALSE(late.interrupted());
  EXPECT_TRUE(late.stopped());
}

TEST(RunControl, WithinTakesTheEarlierDeadline) {
  const Clock::time_point now = Clock::now();
  RunControl control;
  const RunControl budget = control.within(10.0, now);
  EXPECT_EQ(budget.deadline, now + std::chrono::seconds(10));
  // A later budget leaves the earlier deadline; an earlier one replaces it.
  EXPECT_EQ(budget.within(20.0, now).deadline, budget.deadline);
  EXPECT_EQ(budget.within(5.0, now).deadline, now + std::chrono::seconds(5));
  // No budget (0, negative, infinite, NaN): the deadline is unchanged.
  for (double none : {0.0, -1.0, std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::quiet_NaN()})
    EXPECT_EQ(control.within(none, now).deadline, Clock::time_point::max()) << none;
  // The copy keeps the flag and the hooks.
  std::atomic<bool> flag{true};
  control.stop = &flag;
  EXPECT_TRUE(control.within(10.0, now).interrupted());
}

TEST(RunControl, CheckRunsItsHookBeforeReadingTheFlag) {
  std::atomic<bool> flag{false};
  std::vector<std::string> lines;
  RunControl control;
  control.stop = &flag;
  control.on_check = [&] { flag = true; };  // e.g. a pending KeyboardInterrupt becoming the flag
  control.progress = [&](const std::string& line) { lines.push_back(line); };
  EXPECT_FALSE(control.stopped());  // stopped() runs no hook
  EXPECT_TRUE(control.check());
  control.say("stage");
  EXPECT_EQ(lines, std::vector<std::string>{"stage"});
  RunControl silent;
  silent.say("nobody listens");  // no hook: nothing happens
  EXPECT_FALSE(silent.check());
}

}  // namespace
}  // namespace dynid
