#include "identifiability/payload.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.hpp"
#include "core/log_cholesky.hpp"
#include "core/parameters.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/physically_consistent.hpp"

namespace dynid {
namespace {

Vector10d body() {
  RigidInertia<double> b;
  b.mass = 2.0;
  b.first_moment = 2.0 * Eigen::Vector3d(0.05, -0.03, 0.1);
  b.inertia << 0.04, 0.002, -0.001, 0.002, 0.05, 0.003, -0.001, 0.003, 0.02;
  return toStandardVector(b);
}

/// Random per-sample blocks (n x 10) and targets block * phi * gain + noise_j (per joint).
PayloadRows rowsFor(const Vector10d& phi, int samples, const Eigen::VectorXd& noise,
                    std::uint64_t seed, const Eigen::VectorXd& gain = Eigen::VectorXd()) {
  const int n = static_cast<int>(noise.size());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  PayloadRows rows(n, 0);
  const Eigen::MatrixXd none(n, 0);
  for (int k = 0; k < samples; ++k) {
    Eigen::MatrixXd block(n, 10);
    for (int j = 0; j < n; ++j)
      for (int c = 0; c < 10; ++c)
        block(j, c) = normal(rng) * (c == 0 ? 1.0 : c <= 3 ? 10.0 : 50.0);
    Eigen::VectorXd target = block * phi;
    for (int j = 0; j < n; ++j) {
      if (gain.size() > 0) target[j] *= gain[j];
      target[j] += noise[j] * normal(rng);
    }
    rows.add(block, none, target);
  }
  return rows;
}

TEST(Payload, StandardTransformIsTheSpatialChangeOfFrame) {
  Pose<double> a, b;
  a.translation = Eigen::Vector3d(0.1, -0.2, 0.3);
  a.rotation = rotationFromRpy(0.3, -0.5, 1.1);
  b.translation = Eigen::Vector3d(-0.05, 0.02, 0.4);
  b.rotation = rotationFromRpy(-1.0, 0.2, 0.4);
  const Vector10d p = body();
  // Linear, and equal to moving the rigid inertia itself.
  EXPECT_LT(
      (standardTransform(a) * p - toStandardVector(fromStandardVector(p).transformedBy(a))).norm(),
      1e-15 * p.norm() * 10);
  // Composition: (a b) = a after b, to round-off.
  EXPECT_LT((standardTransform(a * b) - standardTransform(a) * standardTransform(b)).norm(), 1e-14);
  EXPECT_LT((standardTransform(Pose<double>::Identity()) - Matrix10d::Identity()).norm(),
            0.0 + 1e-300);
}

TEST(Payload, LeastSquaresOnWhiteNoiseWithPerJointWeights) {
  Eigen::VectorXd noise(3);
  noise << 0.5, 0.05, 0.01;
  const PayloadRows rows = rowsFor(body(), 3000, noise, 3);
  PayloadFitOptions options;
  const PayloadFit fit = fitPayload(rows, options);
  // White residuals: the storage length, the least power of two that keeps 3000 samples in 256
  // batches (identifiability/uncertainty/score_covariance.hpp).
  EXPECT_EQ(fit.batch, 16);
  // The noise per joint estimated to 5 % (3000 samples: its standard error is 1.3 %).
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(fit.noise[j], noise[j], 0.05 * noise[j]) << j;
  // Every parameter within 4.5 of its standard deviations (10 parameters: a miss has
  // probability 7e-5).
  for (int k = 0; k < 10; ++k)
    EXPECT_LT(std::abs(fit.least_squares[k] - body()[k]), 4.5 * std::sqrt(fit.covariance(k, k)))
        << k;
  EXPECT_TRUE(fit.least_squares_consistent);
  EXPECT_TRUE(fit.converged) << fit.termination;
  EXPECT_TRUE(fit.null_directions.cols() == 0);
}

TEST(Payload, AColumnTheDataNeverSeeIsAnUnseenDirectionWithInfiniteVariance) {
  const int n = 2;
  PayloadRows rows(n, 0);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::MatrixXd none(n, 0);
  for (int k = 0; k < 500; ++k) {
    Eigen::MatrixXd block(n, 10);
    for (int j = 0; j < n; ++j)
      for (int c = 0; c < 10; ++c) block(j, c) = c == 8 ? 0.0 : normal(rng);  // Iyz never acts
    rows.add(block, none, block * body() + 0.01 * Eigen::Vector2d(normal(rng), normal(rng)));
  }
  const PayloadFit fit = fitPayload(rows, {});
  ASSERT_EQ(fit.null_directions.cols(), 1);
  EXPECT_NEAR(std::abs(fit.null_directions(8, 0)) / fit.null_directions.col(0).norm(), 1.0, 1e-9);
  EXPECT_TRUE(std::isinf(fit.covariance(8, 8)));
  EXPECT_TRUE(std::isfinite(fit.covariance(0, 0)));
  // The consistent body still is one: the prior holds the unseen direction.
  EXPECT_GE(std::log(pseudoInertia(fit.theta).determinant()), -1e3);
}

TEST(Payload, CorrelatedResidualsWidenTheIntervals) {
  // Smooth regressors (a running mean over 21 samples of random ones, as a real motion's are)
  // with white noise and with the same noise smoothed alike (what a low-pass filter does to a
  // log's torque): the batch grows with the residuals' correlation, and so does the covariance.
  Eigen::VectorXd noise(2);
  noise << 0.1, 0.1;
  const PayloadRows raw = rowsFor(body(), 4000, noise, 9);
  const Eigen::MatrixXd design = raw.design();
  const Eigen::VectorXd e = raw.target() - design * body();
  const auto smoothed = [](const Eigen::MatrixXd& m, int k) {
    Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(2, m.cols());
    int count = 0;
    for (int i = std::max(0, k - 10); i <= std::min(3999, k + 10); ++i, ++count)
      mean += m.middleRows(2 * i, 2);
    return Eigen::MatrixXd(mean * std::sqrt(21.0) / count);
  };
  PayloadRows white(2, 0), smooth(2, 0);
  const Eigen::MatrixXd none(2, 0);
  const Eigen::MatrixXd ecol = e;
  for (int k = 0; k < 4000; ++k) {
    const Eigen::MatrixXd block = smoothed(design, k);
    white.add(block, none, block * body() + e.segment<2>(2 * k));
    smooth.add(block, none, block * body() + smoothed(ecol, k).col(0));
  }
  const PayloadFit a = fitPayload(white, {}), b = fitPayload(smooth, {});
  EXPECT_EQ(a.batch, 16);  // the storage length (4000 samples in 256 batches)
  EXPECT_GT(b.batch, 31);  // the residuals correlated over 21 samples: four times lag 32
  EXPECT_GT(b.covariance(0, 0), 4.0 * a.covariance(0, 0));
}

TEST(Payload, DriveGainsFromAKnownMassOnExactData) {
  Eigen::VectorXd noise = Eigen::VectorXd::Constant(3, 1e-9), gain(3);
  gain << 0.9, 1.05, 1.2;  // measured = gain x true
  const GainFit fit = fitDriveGains(rowsFor(body(), 400, noise, 4, gain), body()[0], std::nullopt);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(fit.scale[j], 1.0 / gain[j], 1e-7) << j;
  EXPECT_LT((fit.theta - body()).norm(), 1e-6 * body().norm());
  EXPECT_THROW(fitDriveGains(rowsFor(body(), 400, noise, 4), 0.0, std::nullopt), InputError);
}

TEST(Payload, PhysicalProblemOnOneBodyKeepsItConsistent) {
  // Data that pull toward an inconsistent body (a negative principal moment): the solution is
  // inside the physical set; a start outside it is refused.
  Vector10d inconsistent = body();
  inconsistent[9] = -0.05;
  const ParameterLayout layout{1, DriveTerms::none()};
  const PhysicalProblem problem = makePhysicalProblem(
      layout, Eigen::MatrixXd::Identity(10, 10) * 100.0, inconsistent * 100.0, body(), 1.0);
  const PhysicalSolution s = solvePhysicalProblem(problem, body());
  EXPECT_TRUE(s.converged) << s.termination;
  EXPECT_TRUE(std::isfinite(problem.cost(s.theta)));
  EXPECT_TRUE(checkPhysicalConsistency(fromStandardVector(Vector10d(s.theta)), 0, "p").empty());
  EXPECT_THROW(solvePhysicalProblem(problem, inconsistent), InputError);
  EXPECT_THROW(
      makePhysicalProblem(layout, Eigen::MatrixXd::Identity(9, 10), inconsistent, body(), 1.0),
      InputError);
}

TEST(Payload, BlockBaseParametersOfTheLastAndTheFirstLink) {
  const Model puma = makePuma560(false);
  const ParameterLayout layout = puma.parameterLayout();
  std::vector<int> last, first;
  for (int k = 0; k < 10; ++k) last.push_back(layout.linkIndex(5, k)), first.push_back(k);
  // A body on the PUMA's wrist: all 10 parameters seen (the arm known).
  const BaseParameters b = blockBaseParameters(puma, last);
  EXPECT_EQ(b.numBase(), 10);
  EXPECT_EQ(b.numStandard(), layout.size());
  const Eigen::VectorXd theta = puma.standardParameters();
  EXPECT_LT((b.project(theta) - theta.segment(layout.linkIndex(5, 0), 10)).norm(), 1e-15);
  // A body on link 1 turns about joint 1's fixed axis only: that moment alone acts.
  const BaseParameters f = blockBaseParameters(puma, first);
  ASSERT_EQ(f.numBase(), 1);
  EXPECT_EQ(f.standard_names[f.independent[0]], "Iyy1");  // link 1's y axis is joint 1's
  EXPECT_THROW(blockBaseParameters(puma, {}), InputError);
  EXPECT_THROW(blockBaseParameters(puma, {layout.size()}), InputError);
}

}  // namespace
}  // namespace dynid
