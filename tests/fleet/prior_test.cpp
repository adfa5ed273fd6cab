#include "analysis/fleet/prior.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.hpp"

namespace dynid {
namespace {

/// `m` robots of `p` parameters: beta_r ~ N(mu, tau^2) per parameter, estimates with their own
/// sigma (from 0.5 to 2 times `sigma`, robot by robot), seeded.
std::vector<FleetMember> drawFleet(int m, const Eigen::VectorXd& mu, const Eigen::VectorXd& tau,
                                   double sigma, std::uint64_t seed,
                                   std::vector<Eigen::VectorXd>* truths = nullptr) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<FleetMember> out;
  for (int r = 0; r < m; ++r) {
    const double s = sigma * (0.5 + 1.5 * r / std::max(1, m - 1));
    Eigen::VectorXd beta(mu.size()), est(mu.size());
    for (Eigen::Index k = 0; k < mu.size(); ++k) {
      beta[k] = mu[k] + tau[k] * normal(rng);
      est[k] = beta[k] + s * normal(rng);
    }
    if (truths) truths->push_back(beta);
    out.push_back(
        {"r" + std::to_string(r), est, Eigen::MatrixXd::Identity(mu.size(), mu.size()) * s * s});
  }
  return out;
}

TEST(PauleMandelSpread, IsZeroWhenTheValuesAgreeWithinTheirVariances) {
  const Eigen::VectorXd x = (Eigen::VectorXd(4) << 1.0, 1.1, 0.9, 1.05).finished();
  EXPECT_EQ(pauleMandelSpread(x, Eigen::VectorXd::Constant(4, 0.04)), 0.0);
}

TEST(PauleMandelSpread, SolvesItsEquation) {
  const Eigen::VectorXd x = (Eigen::VectorXd(5) << 1.0, 3.0, -2.0, 0.5, 4.0).finished();
  const Eigen::VectorXd v = (Eigen::VectorXd(5) << 0.1, 0.2, 0.1, 0.3, 0.5).finished();
  const double t = pauleMandelSpread(x, v);
  ASSERT_GT(t, 0.0);
  const Eigen::ArrayXd w = 1.0 / (v.array() + t);
  const double mean = (w * x.array()).sum() / w.sum();
  // The weighted squares equal m - 1 = 4 to the bisection's 1e-14 relative width (and round-off).
  EXPECT_NEAR((w * (x.array() - mean).square()).sum(), 4.0, 1e-9);
  // Equal variances: the plain sample variance less the common variance.
  const Eigen::VectorXd same = Eigen::VectorXd::Constant(5, 0.2);
  const double var = (x.array() - x.mean()).square().sum() / 4.0;
  EXPECT_NEAR(pauleMandelSpread(x, same), var - 0.2, 1e-10 * var);
}

TEST(SpreadUpperBound, IsTheQProfilesUpperEnd) {
  const Eigen::VectorXd x = (Eigen::VectorXd(5) << 1.0, 3.0, -2.0, 0.5, 4.0).finished();
  const Eigen::VectorXd same = Eigen::VectorXd::Constant(5, 0.2);
  // Equal variances: SS / (0.2 + t) = the chi-square(4) quantile at 2.5 % (0.484418...).
  const double ss = (x.array() - x.mean()).square().sum();
  EXPECT_NEAR(spreadUpperBound(x, same), ss / 0.4844185570879303 - 0.2, 1e-9 * ss);
  EXPECT_GT(spreadUpperBound(x, same), pauleMandelSpread(x, same));
  // Values that agree far within their variances: no spread, not even at the upper end.
  const Eigen::VectorXd close = (Eigen::VectorXd(4) << 1.0, 1.0001, 0.9999, 1.0).finished();
  EXPECT_EQ(spreadUpperBound(close, Eigen::VectorXd::Constant(4, 1.0)), 0.0);
}

TEST(FleetPrior, LearnsTheSpreadAndFlagsNoRobotOfOnePopulation) {
  const Eigen::VectorXd mu = (Eigen::VectorXd(3) << 10.0, -2.0, 0.5).finished();
  const Eigen::VectorXd tau = (Eigen::VectorXd(3) << 0.5, 0.1, 0.0).finished();
  int flagged = 0;
  double spread0 = 0.0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const FleetPrior prior = fleetPrior(drawFleet(200, mu, tau, 0.05, seed));
    for (const FleetVerdict& v : prior.robots) flagged += v.outside ? 1 : 0;
    spread0 += prior.spread[0] / 20.0;
    EXPECT_TRUE(prior.converged);
    // mu's own standard deviation is about tau / sqrt(200): 5 of them.
    EXPECT_NEAR(prior.mean[0], 10.0, 5 * 0.5 / std::sqrt(200.0));
  }
  // 20 fleets at a 1 % family-wise level: at most a robot or two flagged in all.
  EXPECT_LE(flagged, 2);
  // The spread's mean over 20 fleets of 200: within 5 % of 0.5 (its sd is about 0.5 / 20 /
  // sqrt(20)).
  EXPECT_NEAR(spread0, 0.5, 0.025);
}

TEST(FleetPrior, FlagsTheOddRobotAndItsParameterAndLearnsWithoutIt) {
  const Eigen::VectorXd mu = (Eigen::VectorXd(3) << 10.0, -2.0, 0.5).finished();
  const Eigen::VectorXd tau = (Eigen::VectorXd(3) << 0.5, 0.1, 0.02).finished();
  std::vector<FleetMember> fleet = drawFleet(30, mu, tau, 0.05, 7);
  fleet[4].estimate[1] += 1.5;  // 15 tau off on the second parameter
  const FleetPrior prior = fleetPrior(fleet);
  EXPECT_TRUE(prior.robots[4].outside);
  EXPECT_EQ(prior.robots[4].outside_parameters, std::vector<int>{1});
  EXPECT_EQ(prior.robots[4].farthest, 1);
  EXPECT_FALSE(prior.robots[4].learnt_from);
  EXPECT_EQ(prior.learnt_from, 29);
  EXPECT_EQ(prior.rounds, 2);
  for (std::size_t r = 0; r < fleet.size(); ++r)
    if (r != 4) {
      EXPECT_FALSE(prior.robots[r].outside) << r;
    }
  // Learnt without it: the spread of the second parameter is not widened by it.
  EXPECT_LT(prior.spread[1], 0.2);
  // A robot outside keeps its own estimate.
  EXPECT_EQ(prior.robots[4].posterior, fleet[4].estimate);
}

TEST(FleetPrior, ShrinksEachRobotTowardTheFleetByItsOwnCertainty) {
  const Eigen::VectorXd mu = Eigen::VectorXd::Constant(2, 1.0);
  const Eigen::VectorXd tau = Eigen::VectorXd::Constant(2, 0.1);
  std::vector<Eigen::VectorXd> truths;
  std::vector<FleetMember> fleet = drawFleet(40, mu, tau, 0.1, 3, &truths);
  const FleetPrior prior = fleetPrior(fleet);
  double own = 0.0, shrunk = 0.0;
  for (std::size_t r = 0; r < fleet.size(); ++r) {
    const FleetVerdict& v = prior.robots[r];
    ASSERT_FALSE(v.outside);
    for (Eigen::Index k = 0; k < 2; ++k) {
      // One dimension: mu + t / (s + t) (b - mu), variance s t / (s + t).
      const double s = fleet[r].covariance(k, k), t = prior.spread[k] * prior.spread[k];
      EXPECT_NEAR(v.posterior[k],
                  prior.mean[k] + t / (s + t) * (fleet[r].estimate[k] - prior.mean[k]), 1e-12);
      EXPECT_NEAR(v.posterior_std[k], std::sqrt(s * t / (s + t)), 1e-12);
    }
    own += (fleet[r].estimate - truths[r]).squaredNorm();
    shrunk += (v.posterior - truths[r]).squaredNorm();
  }
  // Noise as large as the spread: the prior halves the squared error, about (here 0.4 to 0.6).
  EXPECT_LT(shrunk, 0.7 * own);
}

TEST(FleetPrior, RefusesTooFewRobotsMismatchedSizesAndBadOptions) {
  const Eigen::VectorXd mu = Eigen::VectorXd::Constant(2, 1.0);
  std::vector<FleetMember> fleet = drawFleet(3, mu, mu * 0.1, 0.1, 1);
  EXPECT_NO_THROW(fleetPrior(fleet));
  std::vector<FleetMember> two(fleet.begin(), fleet.begin() + 2);
  EXPECT_THROW(fleetPrior(two), InputError);
  fleet[2].estimate = Eigen::VectorXd::Ones(3);
  try {
    fleetPrior(fleet);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r2"), std::string::npos) << e.what();
  }
  fleet = drawFleet(3, mu, mu * 0.1, 0.1, 1);
  fleet[1].covariance(0, 0) = std::nan("");
  EXPECT_THROW(fleetPrior(fleet), InputError);
  fleet = drawFleet(3, mu, mu * 0.1, 0.1, 1);
  EXPECT_THROW(fleetPrior(fleet, {0.0, 10}), InputError);
  EXPECT_THROW(fleetPrior(fleet, {0.01, 0}), InputError);
}

TEST(FleetPrior, SaysWhenTheSetHasNotSettledInItsRounds) {
  const Eigen::VectorXd mu = Eigen::VectorXd::Constant(1, 1.0);
  std::vector<FleetMember> fleet = drawFleet(20, mu, mu * 0.1, 0.01, 5);
  fleet[3].estimate[0] += 5.0;
  EXPECT_TRUE(fleetPrior(fleet).converged);
  // One round: the robot outside is found, the prior not learnt again without it.
  const FleetPrior once = fleetPrior(fleet, {0.01, 1});
  EXPECT_FALSE(once.converged);
  EXPECT_EQ(once.rounds, 1);
  EXPECT_EQ(once.learnt_from, 20);
  EXPECT_TRUE(once.robots[3].outside);
}

}  // namespace
}  // namespace dynid
