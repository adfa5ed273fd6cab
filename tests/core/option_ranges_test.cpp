#include "core/option_ranges.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Options, EveryRuleIsARangeWithHelpAndNamedOncePerCommand) {
  std::set<std::pair<std::string, std::string>> seen;
  for (const OptionRule& r : optionRules()) {
    EXPECT_TRUE(seen.emplace(r.command, r.name).second) << r.command << " " << r.name;
    EXPECT_LE(r.range.lo, r.range.hi) << r.name;
    EXPECT_EQ(std::string(r.name).find('_'), std::string::npos) << r.name;  // CLI spelling
    EXPECT_GT(std::string(r.help).size(), 3u) << r.name;  // --help takes its words from here
  }
}

TEST(Options, ACommandsOwnRuleComesBeforeTheGeneralOne) {
  EXPECT_EQ(optionRangeText(*findOptionRule("simulate", "harmonics")), ">= 1 and <= 1000");
  EXPECT_EQ(optionRangeText(*findOptionRule("excite", "harmonics")), ">= 2 and <= 50");
  EXPECT_EQ(optionRangeText(*findOptionRule("prepare", "rate")), "0 or >= 0.001 and <= 1e+07");
  EXPECT_EQ(findOptionRule("simulate", "no-such-option"), nullptr);
  EXPECT_NO_THROW(checkOption("demo", "refine-iterations", 0, "--refine-iterations"));
  EXPECT_THROW(checkOption("study", "refine-iterations", 0, "--refine-iterations"), InputError);
}

TEST(Options, MessagesNameTheCallersSpellingAndTheRange) {
  try {
    checkOption("identify", "prior-weight", 0.0, "prior_weight");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "prior_weight must be > 0 and <= 1e+12, not 0");
  }
  try {
    checkOption("", "threads", 300, "--threads");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--threads must be >= 0 and <= 256, not 300");
  }
  EXPECT_THROW(checkOption("", "no-rule", std::nan(""), "x"), InputError);  // finite, always
  EXPECT_NO_THROW(checkOption("", "no-rule", -1e300, "x"));
}

}  // namespace
}  // namespace dynid
