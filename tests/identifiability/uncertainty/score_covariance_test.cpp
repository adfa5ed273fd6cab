#include "identifiability/uncertainty/score_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "core/errors.hpp"

namespace dynid {
namespace {

/// Two joints' AR(1) residuals e_k = rho e_{k-1} + w_k (rho 0: white), rows k n + j.
Eigen::VectorXd arNoise(int samples, double rho, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd out(2 * samples);
  double x[2] = {0.0, 0.0};
  for (int k = 0; k < samples; ++k)
    for (int j = 0; j < 2; ++j) {
      x[j] = rho * x[j] + normal(rng);
      out[2 * k + j] = x[j];
    }
  return out;
}

/// A smooth design: two joints' rows of 3 unknowns (slow sinusoids, as excitation trajectories).
Eigen::MatrixXd design(int samples) {
  Eigen::MatrixXd a(2 * samples, 3);
  for (int k = 0; k < samples; ++k) {
    const double t = 0.001 * k;
    a.row(2 * k) << 1.0, std::sin(2.0 * t), std::cos(0.7 * t);
    a.row(2 * k + 1) << 0.5, std::cos(1.3 * t), std::sin(3.1 * t + 1.0);
  }
  return a;
}

/// The least-squares fit, its covariance (CR2), the batch-means sandwich and the white one.
struct Fit {
  Eigen::Vector3d x;
  Eigen::Matrix3d robust, plain, white;
  int batch = 0;
};
Fit fit(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, int batch = 0) {
  Fit out;
  const Eigen::Matrix3d bread = (a.transpose() * a).inverse();
  out.x = bread * a.transpose() * y;
  const Eigen::VectorXd e = y - a * out.x;
  const Eigen::Index samples = e.size() / 2;
  ScoreCovariance scores(3, 2, samples, batch);
  for (Eigen::Index k = 0; k < samples; ++k)
    scores.add(a.middleRows(2 * k, 2), e.segment(2 * k, 2));
  out.batch = scores.batch();
  out.robust = scores.covariance();
  out.plain = bread * scores.meat() * bread;
  out.white = e.squaredNorm() / static_cast<double>(e.size() - 3) * bread;
  return out;
}

TEST(ScoreCovariance, BatchFollowsTheResidualsCorrelation) {
  const Eigen::MatrixXd a = design(30000);
  // 30000 samples are stored in batches of 128 (the least power of two that keeps them in 256
  // batches): white residuals take that length.
  EXPECT_EQ(fit(a, arNoise(30000, 0.0, 1)).batch, 128);
  // rho = 0.95: rho^32 = 0.19, rho^64 = 0.04: the first power-of-two lag below 0.05 is 64 (its
  // sampling error, about 0.04 here, may put it at 128): batches of four times that.
  const int batch = fit(a, arNoise(30000, 0.95, 2)).batch;
  EXPECT_GE(batch, 256);
  EXPECT_LE(batch, 512);
  // At most a thirtieth of the samples: 3000 samples allow 64 (100 rounded down to a power of 2).
  EXPECT_EQ(fit(design(3000), arNoise(3000, 0.999, 3)).batch, 64);
  // Few samples: batches of one when the residuals are white.
  EXPECT_EQ(fit(design(200), arNoise(200, 0.0, 4)).batch, 1);
  // A fixed length is any length.
  EXPECT_EQ(fit(a, arNoise(30000, 0.95, 2), 7).batch, 7);
}

TEST(ScoreCovariance, WhiteResidualsGiveTheClassicalCovariance) {
  // With white residuals the policy estimates sigma^2 (A^T A)^-1: each fit's variance has the
  // random error of about 230 batches (sqrt(2 / 230) = 9 %); the mean ratio over 20 fits and 3
  // parameters has about 1.2 %: within 5 % of 1.
  const Eigen::MatrixXd a = design(30000);
  double sum = 0.0;
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    const Fit f = fit(a, arNoise(30000, 0.0, seed));
    for (int i = 0; i < 3; ++i) sum += f.robust(i, i) / f.white(i, i);
  }
  EXPECT_NEAR(sum / 60.0, 1.0, 0.05);
}

TEST(ScoreCovariance, IsTheBiasReducedSandwichOverBatches) {
  // Batches of 7: the batch means against the sum written out, and the covariance against CR2
  // computed in residual space, sum_b H^-1 A_b^T (I - P_bb)^-1/2 e_b (...)^T H^-1 with P_bb the
  // batch's block of the hat matrix A H^-1 A^T: an independent computation of the same number.
  const Eigen::MatrixXd a = design(100);
  const Eigen::VectorXd y = a * Eigen::Vector3d(1.0, 2.0, 3.0) + arNoise(100, 0.5, 5);
  const Fit f = fit(a, y, 7);
  const Eigen::Matrix3d bread = (a.transpose() * a).inverse();
  const Eigen::VectorXd e = y - a * f.x;
  Eigen::Matrix3d direct = Eigen::Matrix3d::Zero(), cr2 = Eigen::Matrix3d::Zero();
  for (int first = 0; first < 100; first += 7) {
    const int rows = 2 * (std::min(100, first + 7) - first);
    const Eigen::MatrixXd ab = a.middleRows(2 * first, rows);
    const Eigen::VectorXd eb = e.segment(2 * first, rows);
    const Eigen::Vector3d score = ab.transpose() * eb;
    direct += score * score.transpose();
    const Eigen::MatrixXd p = Eigen::MatrixXd::Identity(rows, rows) - ab * bread * ab.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(p);
    const Eigen::MatrixXd root = eigen.eigenvectors() *
                                 eigen.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal() *
                                 eigen.eigenvectors().transpose();
    const Eigen::Vector3d step = bread * ab.transpose() * root * eb;
    cr2 += step * step.transpose();
  }
  // rows / (rows - dof) = 200 / 197.
  EXPECT_LT((f.plain - bread * direct * bread * 200.0 / 197.0).norm(), 1e-10 * f.plain.norm());
  EXPECT_LT((f.robust - cr2).norm(), 1e-9 * cr2.norm());
}

TEST(ScoreCovariance, BlocksGiveWhatSamplesGive) {
  // The same samples added one by one and as blocks cut at the stored batches' ends (3000 samples
  // stored in batches of 16): the same covariance to round-off; a block across an end refused.
  const Eigen::MatrixXd a = design(3000);
  const Eigen::VectorXd e = arNoise(3000, 0.7, 8);
  ScoreCovariance one(3, 2, 3000), blocks(3, 2, 3000);
  ASSERT_EQ(blocks.storageLength(), 16);
  for (int k = 0; k < 3000; ++k) one.add(a.middleRows(2 * k, 2), e.segment(2 * k, 2));
  for (int first = 0; first < 3000;) {
    const int count = std::min({first % 16 == 0 ? 5 : 16 - first % 16, 3000 - first});
    const Eigen::Map<const Eigen::MatrixXd> residuals(e.data() + 2 * first, 2, count);
    blocks.add(ScoreCovariance::prepare(a.middleRows(2 * first, 2 * count), residuals));
    first += count;
  }
  EXPECT_EQ(blocks.samples(), 3000);
  EXPECT_EQ(blocks.batch(), one.batch());
  EXPECT_EQ(blocks.autocorrelation(), one.autocorrelation());
  EXPECT_LT((blocks.covariance() - one.covariance()).norm(), 1e-12 * one.covariance().norm());
  ScoreCovariance crossing(3, 2, 3000);
  const Eigen::Map<const Eigen::MatrixXd> residuals(e.data(), 2, 17);
  EXPECT_THROW(crossing.add(ScoreCovariance::prepare(a.topRows(34), residuals)), InputError);
}

// The point of the policy: with correlated residuals the white intervals cover the truth far less
// often than they claim, the policy's as often (200 fits of AR(0.9) residuals).
TEST(ScoreCovariance, IntervalsCoverTheTruthWithCorrelatedResiduals) {
  const Eigen::MatrixXd a = design(6000);
  const Eigen::Vector3d truth(1.0, -2.0, 0.5);
  int covered = 0, covered_white = 0, total = 0;
  for (std::uint64_t seed = 10; seed < 210; ++seed) {
    const Fit f = fit(a, a * truth + arNoise(6000, 0.9, seed));
    for (int i = 0; i < 3; ++i) {
      const double error = std::abs(f.x[i] - truth[i]);
      covered += error <= 1.959964 * std::sqrt(f.robust(i, i));
      covered_white += error <= 1.959964 * std::sqrt(f.white(i, i));
      ++total;
    }
  }
  const double coverage = static_cast<double>(covered) / total;
  const double white = static_cast<double>(covered_white) / total;
  RecordProperty("coverage", std::to_string(coverage));
  RecordProperty("coverage_white", std::to_string(white));
  // 600 intervals: binomial sd 0.9 %; the variance estimate has its own error (about 190 batches
  // per fit, half a point of coverage): 92-98 % is 3 sd about 95 %.
  EXPECT_GE(coverage, 0.92) << coverage;
  EXPECT_LE(coverage, 0.98) << coverage;
  // AR(0.9) inflates the variance by about (1 + rho) / (1 - rho) = 19: white intervals are a
  // quarter as wide as they should be and cover about 35 %.
  EXPECT_LT(white, 0.6) << white;
}

TEST(ScoreCovariance, RefusesBadSizes) {
  EXPECT_THROW(ScoreCovariance(0, 2, 10), InputError);
  EXPECT_THROW(ScoreCovariance(3, 0, 10), InputError);
  EXPECT_THROW(ScoreCovariance(3, 2, 10, -1), InputError);
  ScoreCovariance scores(3, 2, 10);
  EXPECT_THROW(scores.add(Eigen::MatrixXd::Zero(2, 2), Eigen::VectorXd::Zero(2)), InputError);
  // Rows that never see the third unknown: no covariance.
  for (int k = 0; k < 10; ++k)
    scores.add(Eigen::MatrixXd::Identity(2, 3), Eigen::VectorXd::Ones(2));
  EXPECT_THROW(scores.covariance(), NumericalError);
}

}  // namespace
}  // namespace dynid
