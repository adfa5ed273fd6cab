#include "search/cobyla.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/errors.hpp"

namespace dynid {
namespace {

/// (x0 - 1)^2 + (x1 - 2)^2: minimum at (1, 2).
CobylaProblem bowl() {
  CobylaProblem p;
  p.dimension = 2;
  p.objective = [](const double* x) -> std::optional<double> {
    return std::pow(x[0] - 1.0, 2) + std::pow(x[1] - 2.0, 2);
  };
  p.initial_step = {0.5};
  p.max_evaluations = 2000;
  p.xtol_rel = 1e-10;
  return p;
}

TEST(Cobyla, FindsTheMinimumUnderBoundsAndConstraints) {
  std::vector<double> x = {0.0, 0.0};
  EXPECT_EQ(runCobyla(bowl(), x).end, CobylaEnd::kConverged);
  // xtol_rel 1e-10 on a smooth bowl: within 1e-6 of the minimiser (COBYLA's linear models).
  EXPECT_NEAR(x[0], 1.0, 1e-6);
  EXPECT_NEAR(x[1], 2.0, 1e-6);

  CobylaProblem bounded = bowl();  // x1 <= 1.5: the minimum moves onto the bound
  bounded.lower = {-5.0, -5.0};
  bounded.upper = {5.0, 1.5};
  x = {0.0, 0.0};
  runCobyla(bounded, x);
  EXPECT_NEAR(x[1], 1.5, 1e-6);

  CobylaProblem constrained = bowl();  // x0 + x1 <= 1 and x0 = x1: (0.5, 0.5)
  constrained.inequalities = 1;
  constrained.inequality = [](const double* x, double* c) { c[0] = x[0] + x[1] - 1.0; };
  constrained.equality = [](const double* x) { return x[0] - x[1]; };
  constrained.equality_tolerance = 1e-12;
  x = {0.0, 0.0};
  runCobyla(constrained, x);
  EXPECT_NEAR(x[0], 0.5, 1e-6);
  EXPECT_NEAR(x[1], 0.5, 1e-6);
}

TEST(Cobyla, TheObjectiveStopsTheRunAndTheBudgetEndsIt) {
  int calls = 0;
  CobylaProblem p = bowl();
  const auto f = p.objective;
  p.objective = [&](const double* x) -> std::optional<double> {
    if (++calls == 5) return std::nullopt;
    return f(x);
  };
  std::vector<double> x = {0.0, 0.0};
  EXPECT_EQ(runCobyla(p, x).end, CobylaEnd::kStopped);
  EXPECT_EQ(calls, 5);  // no evaluation after the stop

  CobylaProblem short_run = bowl();
  short_run.max_evaluations = 3;
  x = {0.0, 0.0};
  EXPECT_EQ(runCobyla(short_run, x).end, CobylaEnd::kEvaluations);
}

TEST(Cobyla, ACallbackThatThrowsEndsTheRunAsAFailure) {
  CobylaProblem p = bowl();
  p.objective = [](const double*) -> std::optional<double> { throw InputError("bad"); };
  std::vector<double> x = {0.0, 0.0};
  const CobylaOutcome out = runCobyla(p, x);
  EXPECT_EQ(out.end, CobylaEnd::kFailed);
  EXPECT_FALSE(out.message.empty());
}

TEST(Cobyla, SizesThatDoNotMatchAreRefused) {
  std::vector<double> x = {0.0};
  EXPECT_THROW(runCobyla(bowl(), x), InputError);
  CobylaProblem p = bowl();
  p.lower = {0.0};
  x = {0.0, 0.0};
  EXPECT_THROW(runCobyla(p, x), InputError);
  p = bowl();
  p.initial_step = {0.1, 0.1, 0.1};
  EXPECT_THROW(runCobyla(p, x), InputError);
}

}  // namespace
}  // namespace dynid
