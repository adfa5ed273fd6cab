#include "core/regressor.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "core/model-inl.hpp"
#include "core/regressor-inl.hpp"
#include "core/rnea-inl.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

class RegressorOnModels : public ::testing::TestWithParam<int> {
 protected:
  Model model() const {
    if (GetParam() == 0) return makePuma560(false);
    if (GetParam() == 1) return makePuma560(true);
    return test::randomTree(200 + GetParam(), {.drives = GetParam() % 2 == 1});
  }
};

TEST_P(RegressorOnModels, TimesThetaEqualsRnea) {
  const Model m = model();
  Data data(m);
  std::mt19937_64 rng(GetParam());
  const int n = m.numJoints();
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = test::randomVector(rng, n, 2.5), dq = test::randomVector(rng, n, 2.0),
                          ddq = test::randomVector(rng, n, 4.0);
    const Eigen::MatrixXd Y = jointTorqueRegressor(m, data, q, dq, ddq);
    ASSERT_EQ(Y.rows(), n);
    ASSERT_EQ(Y.cols(), m.parameterLayout().size());
    const Eigen::VectorXd tau = rnea(m, data, q, dq, ddq);
    // The required bound: 1e-10 N m on torques of order 10-100 N m.
    EXPECT_LT((Y * m.standardParameters() - tau).cwiseAbs().maxCoeff(), 1e-10) << "trial " << trial;
    // Linear in theta: any other parameter vector, through setStandardParameters and RNEA.
    Model other = m;
    const Eigen::VectorXd theta = test::randomVector(rng, static_cast<int>(Y.cols()), 1.0);
    other.setStandardParameters(theta);
    Data other_data(other);
    EXPECT_LT((Y * theta - rnea(other, other_data, q, dq, ddq)).cwiseAbs().maxCoeff(), 1e-10);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, RegressorOnModels, ::testing::Range(0, 6));

TEST(Regressor, EveryDriveTermSubsetMatchesRnea) {
  // Each subset of the drive-term table (64: ia, fv, fc, fo, fa, fs): the columns land where the
  // layout says and Y theta equals RNEA, also at rest on one joint (sign 0: Fc, Fa and Fs vanish,
  // Fo stays).
  const Model all = test::randomTree(31, {.num_bodies = 5, .drives = true});
  std::mt19937_64 rng(31);
  for (unsigned mask = 0; mask < (1u << kDriveTermCount); ++mask) {
    Model m = all;
    m.setDriveTerms(DriveTerms{mask});
    Data data(m);
    const Eigen::VectorXd q = test::randomVector(rng, 5, 2.0),
                          ddq = test::randomVector(rng, 5, 3.0);
    Eigen::VectorXd dq = test::randomVector(rng, 5, 2.0);
    dq[2] = 0.0;
    const Eigen::MatrixXd Y = jointTorqueRegressor(m, data, q, dq, ddq);
    ASSERT_EQ(Y.cols(), 5 * (10 + m.driveTerms().count()));
    const Eigen::VectorXd tau = rnea(m, data, q, dq, ddq);
    // Round-off of torques of order 10 N m.
    EXPECT_LT((Y * m.standardParameters() - tau).cwiseAbs().maxCoeff(), 1e-10) << "mask " << mask;
    // The offset column is 1 whatever the velocity, the asymmetry column |sign(dq)|.
    const ParameterLayout layout = m.parameterLayout();
    if (m.driveTerms().has(DriveTerm::kOffset)) {
      EXPECT_EQ(Y(2, layout.driveIndex(2, DriveTerm::kOffset)), 1.0) << "mask " << mask;
    }
    if (m.driveTerms().has(DriveTerm::kCoulombAsymmetry)) {
      EXPECT_EQ(Y(2, layout.driveIndex(2, DriveTerm::kCoulombAsymmetry)), 0.0);
      EXPECT_EQ(Y(1, layout.driveIndex(1, DriveTerm::kCoulombAsymmetry)), 1.0);
    }
  }
}

TEST(Regressor, JetScalarMatchesDouble) {
  using Jet = ceres::Jet<double, 2>;
  const Model m = makePuma560(true);
  const ModelTpl<Jet> mj = m.cast<Jet>();
  Data data(m);
  DataTpl<Jet> data_j(mj);
  const Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.4),
                        ddq = Eigen::VectorXd::Constant(6, -0.3);
  VectorX<Jet> qj = q.cast<Jet>();
  qj[1].v[0] = 1.0;  // d/dq2
  const MatrixX<Jet> Yj = jointTorqueRegressor(mj, data_j, qj, dq.cast<Jet>(), ddq.cast<Jet>());
  const Eigen::MatrixXd Y = jointTorqueRegressor(m, data, q, dq, ddq);
  Eigen::VectorXd qp = q, qm = q;
  qp[1] += 1e-6, qm[1] -= 1e-6;
  const Eigen::MatrixXd Yp = jointTorqueRegressor(m, data, qp, dq, ddq);
  const Eigen::MatrixXd Ym = jointTorqueRegressor(m, data, qm, dq, ddq);
  for (int r = 0; r < Y.rows(); ++r)
    for (int c = 0; c < Y.cols(); ++c) {
      EXPECT_NEAR(Yj(r, c).a, Y(r, c), 1e-13);
      // Central difference: truncation and cancellation ~ 1e-9 on entries of order 1.
      EXPECT_NEAR(Yj(r, c).v[0], (Yp(r, c) - Ym(r, c)) / 2e-6, 1e-6 * (1 + std::abs(Y(r, c))));
    }
}

}  // namespace
}  // namespace dynid
