#include "identifiability/excitation.hpp"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "identifiability/observation.hpp"

namespace dynid {
namespace {

/// A seeded motion of the PUMA: smooth sums of sines, different on every joint.
Trajectory wavyMotion(int samples) {
  Trajectory t;
  t.resize(6, samples);
  for (int k = 0; k < samples; ++k) {
    t.time[k] = 0.01 * k;
    for (int j = 0; j < 6; ++j) {
      const double w = 0.7 + 0.45 * j, s = t.time[k];
      t.q(j, k) = 0.6 * std::sin(w * s + j) + 0.2 * std::sin(2.3 * w * s);
      t.dq(j, k) = 0.6 * w * std::cos(w * s + j) + 0.46 * w * std::cos(2.3 * w * s);
      t.ddq(j, k) = -0.6 * w * w * std::sin(w * s + j) - 1.058 * w * w * std::sin(2.3 * w * s);
    }
  }
  return t;
}

TEST(Excitation, ScoresEqualTheDenseComputation) {
  const Model puma = makePuma560(true);
  const BaseParameters base = structuralBaseParameters(puma);
  const Trajectory motion = wavyMotion(3000);  // spans several 1024-row blocks of the TallQr
  const MotionScore s = scoreMotion(puma, base, motion, 0.05);
  const Eigen::MatrixXd W1 = base.baseRegressor(observationFromTrajectory(puma, motion).W);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(W1);
  const Eigen::VectorXd sv = svd.singularValues();
  // 1e-9 relative: QR against SVD of a matrix with condition number ~1e3 to 1e4.
  EXPECT_NEAR(s.condition, sv[0] / sv[sv.size() - 1], 1e-9 * s.condition);
  EXPECT_NEAR(s.condition_unit, scaledConditionNumber(W1), 1e-9 * s.condition_unit);
  const Eigen::MatrixXd information = W1.transpose() * W1;
  const double rows = static_cast<double>(W1.rows());
  EXPECT_NEAR(s.log_det, std::log((information / rows).determinant()), 1e-8 * std::abs(s.log_det));
  const Eigen::VectorXd std_dev =
      0.05 * information.inverse().diagonal().cwiseSqrt();  // (W1^T W1)^-1 directly
  const Eigen::VectorXd scale = baseParameterScale(base.project(puma.standardParameters()));
  double mean_square = 0.0;
  for (int j = 0; j < base.numBase(); ++j) {
    EXPECT_NEAR(s.std_dev[j], std_dev[j], 1e-7 * std_dev[j]) << base.baseName(j);
    EXPECT_NEAR(s.relative_std[j], 100.0 * std_dev[j] / scale[j], 1e-6 * s.relative_std[j]);
    mean_square += std::pow(std_dev[j] / scale[j], 2) / base.numBase();
  }
  EXPECT_NEAR(s.relative_rms, std::sqrt(mean_square), 1e-6 * s.relative_rms);
  EXPECT_EQ(s.samples, 3000);
}

TEST(Excitation, AMotionThatLeavesAParameterUnseenIsRankDeficient) {
  const Model puma = makePuma560(false);
  const BaseParameters base = structuralBaseParameters(puma);
  Trajectory still = wavyMotion(500);
  still.dq.setZero();
  still.ddq.setZero();  // a static motion sees gravity only
  const MotionScore s = scoreMotion(puma, base, still, 0.05);
  // Infinite, or (round-off leaving an unseen column's |R_jj| at ~1e-16 rather than 0) huge.
  EXPECT_GT(s.condition_unit, 1e10);
  EXPECT_GT(s.std_dev.maxCoeff(), 1e3);  // [kg m^2 or kg m] at 0.05 N m of noise
}

TEST(Excitation, BadInputIsRefused) {
  const Model puma = makePuma560(false);
  const BaseParameters base = structuralBaseParameters(puma);
  Trajectory t = wavyMotion(10);
  EXPECT_THROW(scoreMotion(puma, base, t, 0.0), InputError);
  EXPECT_THROW(scoreMotion(puma, base, Trajectory{}, 0.05), InputError);
  t.q(2, 3) = std::nan("");
  EXPECT_THROW(scoreMotion(puma, base, t, 0.05), InputError);
  EXPECT_THROW(scoreMotion(makePuma560(true), base, wavyMotion(10), 0.05), InputError);
}

}  // namespace
}  // namespace dynid
