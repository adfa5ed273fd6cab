#include "identifiability/least_squares.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "tests/common/identification.hpp"

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

using test::pumaBase;
using test::pumaTrajectory;

TEST(LeastSquares, JointRmsIsPerJointOverTheStackedRows) {
  // Rows k n + j, n = 2 joints, 2 samples: joint 0 holds 3 and -4, joint 1 holds 1 and 1.
  Eigen::VectorXd r(4);
  r << 3.0, 1.0, -4.0, 1.0;
  const Eigen::VectorXd rms = jointRms(r, 2);
  ASSERT_EQ(rms.size(), 2);
  EXPECT_DOUBLE_EQ(rms[0], std::sqrt(12.5));  // sqrt((9 + 16) / 2)
  EXPECT_DOUBLE_EQ(rms[1], 1.0);
  // No samples: zero for every joint, not 0/0.
  const Eigen::VectorXd none = jointRms(Eigen::VectorXd(), 3);
  ASSERT_EQ(none.size(), 3);
  EXPECT_EQ(none.cwiseAbs().maxCoeff(), 0.0);
}
TEST(LeastSquares, NoiseFreeDataGiveTheTrueProjection) {
  for (bool drives : {false, true}) {
    const Model model = makePuma560(drives);
    const BaseParameters base = pumaBase(model);
    const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 10.0, 0.0, 1));
    const Eigen::VectorXd truth = base.project(model.standardParameters());
    for (auto method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
      const BaseEstimate e = estimateBaseParameters(base, train, method);
      // The required bound: 1e-8 relative, on the vector (several base values are exact zeros).
      EXPECT_LT((e.beta - truth).norm(), 1e-8 * truth.norm())
          << "drives " << drives << ", " << leastSquaresMethodName(method);
      EXPECT_LT(e.residual_rms.maxCoeff(), 1e-8);
      EXPECT_TRUE(std::isfinite(e.condition_number));
    }
  }
}

TEST(LeastSquares, ReportedSigmaCoversTheErrors) {
  // Torque noise only (noise on q or dq would bias least squares): over seeded trials, at least
  // 95 % of the base-parameter errors lie within 3 reported standard deviations (99.7 % expected
  // for Gaussian estimates).
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Eigen::VectorXd truth = base.project(model.standardParameters());
  for (auto method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    int within = 0, total = 0;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const Observation train =
          observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.05, seed));
      const BaseEstimate e = estimateBaseParameters(base, train, method);
      for (int j = 0; j < base.numBase(); ++j, ++total)
        if (std::abs(e.beta[j] - truth[j]) <= 3.0 * e.std_dev[j]) ++within;
    }
    EXPECT_GE(within, 0.95 * total)
        << leastSquaresMethodName(method) << ": " << within << "/" << total;
  }
}

TEST(LeastSquares, ValidationOnHeldOutData) {
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.02, 1));
  const Observation test =
      observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.0, 2, 1.3));
  const BaseEstimate e = estimateBaseParameters(base, train, LeastSquaresMethod::kWeighted);
  const Validation v = validateBaseEstimate(base, e.beta, test);
  ASSERT_EQ(v.torque_rms.size(), 6);
  // Noise of 0.02 N m on 5000 samples leaves prediction errors far below the noise.
  EXPECT_LT(v.torque_rms.maxCoeff(), 0.02);
  EXPECT_LT(v.normalised_rms.maxCoeff(), 0.05);
  // The torque noise estimated per joint is close to the simulated 0.02 N m.
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(e.joint_sigma[j], 0.02, 0.002) << j;
}

TEST(LeastSquares, RelativeErrorsAndBothConditionNumbersFromTheirDefinitions) {
  const Model model = makePuma560(false);
  const BaseParameters base = pumaBase(model);
  const Observation obs = observationFromTrajectory(model, pumaTrajectory(model, 2.0, 0.2, 5));
  const BaseEstimate e = estimateBaseParameters(base, obs, LeastSquaresMethod::kOrdinary);
  // |tau - W1 beta| / |tau| over every row, and per joint, computed directly.
  const Eigen::MatrixXd W1 = base.baseRegressor(obs.W);
  const Eigen::VectorXd residual = obs.tau - W1 * e.beta;
  // Round-off of sums over 12000 rows.
  EXPECT_NEAR(e.relative_error, residual.norm() / obs.tau.norm(), 1e-12);
  for (int j = 0; j < 6; ++j) {
    double r2 = 0.0, t2 = 0.0;
    for (int k = 0; k < obs.num_samples; ++k)
      r2 += residual[k * 6 + j] * residual[k * 6 + j],
          t2 += obs.tau[k * 6 + j] * obs.tau[k * 6 + j];
    EXPECT_NEAR(e.joint_relative_error[j], std::sqrt(r2 / t2), 1e-12) << j;
  }
  // Condition numbers: the SVD of W1 as it is, and with unit-norm columns.
  const auto condition = [](const Eigen::MatrixXd& m) {
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues();
    return s[0] / s[s.size() - 1];
  };
  const Eigen::VectorXd norms = W1.colwise().norm().transpose();
  // Two routes to the same singular values (QR then SVD of R, or SVD of W1): 1e-8 relative for
  // condition numbers up to 1e5.
  EXPECT_NEAR(e.condition_number_unscaled / condition(W1), 1.0, 1e-8);
  EXPECT_NEAR(e.condition_number / condition(W1 * norms.cwiseInverse().asDiagonal()), 1.0, 1e-8);
  // Physical units make the unscaled one the larger here (masses against light wrist inertias).
  EXPECT_GT(e.condition_number_unscaled, e.condition_number);
}

TEST(LeastSquares, IndependenceIsTheUnexplainedShareOfEachColumn) {
  const Model model = makePuma560(false);
  const BaseParameters base = pumaBase(model);
  const Observation obs = observationFromTrajectory(model, pumaTrajectory(model, 2.0, 0.2, 5));
  const BaseEstimate e = estimateBaseParameters(base, obs, LeastSquaresMethod::kOrdinary);
  const Eigen::MatrixXd W1 = base.baseRegressor(obs.W);
  ASSERT_EQ(e.independence.size(), W1.cols());
  // The definition: each column regressed on all the others by least squares; the share of its
  // norm that the others leave unexplained.
  for (Eigen::Index j = 0; j < W1.cols(); ++j) {
    Eigen::MatrixXd others(W1.rows(), W1.cols() - 1);
    others << W1.leftCols(j), W1.rightCols(W1.cols() - 1 - j);
    const Eigen::VectorXd fit = others.colPivHouseholderQr().solve(W1.col(j));
    const double unexplained = (W1.col(j) - others * fit).norm() / W1.col(j).norm();
    // Two factorisations of the same columns: round-off relative to the condition number (~1e2).
    EXPECT_NEAR(e.independence[j], unexplained, 1e-9 + 1e-7 * unexplained) << base.baseName(j);
    EXPECT_GT(e.independence[j], 0.0);
    EXPECT_LE(e.independence[j], 1.0 + 1e-12);
  }
}

TEST(LeastSquares, RefusesRankDeficientData) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  Trajectory t = pumaTrajectory(model, 2.0, 0.0, 1);
  t.q.row(0).setZero();  // joint 1 never moves
  t.dq.row(0).setZero();
  t.ddq.row(0).setZero();
  try {
    estimateBaseParameters(base, observationFromTrajectory(model, t),
                           LeastSquaresMethod::kOrdinary);
    FAIL();
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("do not excite"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Iyy1R"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
