#include "analysis/studies/correlation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Metrics, PearsonAndSpearmanOnKnownSeries) {
  const std::vector<double> x = {1, 2, 3, 4, 5};
  EXPECT_NEAR(pearson(x, {2, 4, 6, 8, 10}), 1.0, 1e-15);  // exact line: r = 1 to round-off
  EXPECT_NEAR(pearson(x, {5, 4, 3, 2, 1}), -1.0, 1e-15);
  // Monotone but not linear: Spearman 1, Pearson below 1.
  const std::vector<double> cubes = {1, 8, 27, 64, 125};
  EXPECT_NEAR(spearman(x, cubes), 1.0, 1e-15);
  EXPECT_LT(pearson(x, cubes), 0.99);
  // Ties share their average rank: ranks (1, 2.5, 2.5, 4) against (1, 2, 3, 4).
  EXPECT_NEAR(spearman({1, 2, 2, 3}, {1, 2, 3, 4}), pearson({1, 2.5, 2.5, 4}, {1, 2, 3, 4}), 1e-15);
  EXPECT_TRUE(std::isnan(pearson({1, 2}, {1, 2})));
  EXPECT_TRUE(std::isnan(pearson({1, 1, 1}, {1, 2, 3})));
  EXPECT_THROW(pearson({1, 2, 3}, {1, 2}), InputError);
}

}  // namespace
}  // namespace dynid
