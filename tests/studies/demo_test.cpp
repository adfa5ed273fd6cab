#include "analysis/studies/demo.hpp"

#include <gtest/gtest.h>

#include <atomic>

namespace dynid {
namespace {

// Ctrl-C before the searches: the demo returns what finished (the least-squares rows), marked
// interrupted, instead of running on. (The full quick demo runs in cli/command_demo_test's
// DemoQuickMeetsTheStudysClaimsAndItsReportsAgreeWithTheJson.)
TEST(Demo, StopsAfterTheCurrentStageWhenInterrupted) {
  std::atomic<bool> stop{true};
  std::vector<std::string> stages;
  DemoOptions options;
  options.quick = true;
  options.threads = 1;
  options.control.stop = &stop;
  options.control.progress = [&](const std::string& s) { stages.push_back(s); };
  const DemoResult result = runDemo(options);
  EXPECT_TRUE(result.interrupted);
  ASSERT_EQ(result.methods.size(), 2u);
  EXPECT_EQ(result.methods[0].key, "ols");
  EXPECT_EQ(result.methods[1].key, "wls");
  EXPECT_EQ(result.identifiability.num_base, 36);
  EXPECT_EQ(result.settings.train_seconds, 4.0);
  EXPECT_FALSE(stages.empty());
}

}  // namespace
}  // namespace dynid
