#include "core/rnea.hpp"

#include <gtest/gtest.h>

#include "core/crba.hpp"
#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Rnea, PlanarTwoLinkMatchesTheTextbook) {
  const test::Planar2R arm;
  const Model model = arm.model();
  Data data(model);
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector2d q = test::randomVector(rng, 2, 3.0), dq = test::randomVector(rng, 2, 2.0),
                          ddq = test::randomVector(rng, 2, 2.0);
    const Eigen::Vector2d expected = arm.massMatrix(q) * ddq + arm.coriolis(q, dq) + arm.gravity(q);
    // Round-off on torques of order 10 N m.
    EXPECT_LT((rnea(model, data, q, dq, ddq) - expected).norm(), 1e-12);
  }
}

class RneaOnModels : public ::testing::TestWithParam<int> {
 protected:
  Model model() const {
    if (GetParam() == 0) return makePuma560(false);
    if (GetParam() == 1) return makePuma560(true);
    return test::randomTree(100 + GetParam(), {.drives = GetParam() % 2 == 1});
  }
};

TEST_P(RneaOnModels, EqualsMassMatrixTimesAccelerationPlusBias) {
  const Model m = model();
  Data data(m);
  std::mt19937_64 rng(GetParam());
  const int n = m.numJoints();
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = test::randomVector(rng, n, 2.0), dq = test::randomVector(rng, n, 2.0),
                          ddq = test::randomVector(rng, n, 3.0);
    const Eigen::VectorXd tau = rnea(m, data, q, dq, ddq);
    const Eigen::VectorXd bias = rnea(m, data, q, dq, Eigen::VectorXd::Zero(n));
    const Eigen::MatrixXd M = crba(m, data, q);
    // Mixed tolerance: round-off relative to the torque scale (tens of N m).
    EXPECT_LT((tau - (M * ddq + bias)).norm(), 1e-12 * (1.0 + tau.norm())) << "trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, RneaOnModels, ::testing::Range(0, 6));

TEST(Rnea, DrivesAddRotorInertiaAndFriction) {
  const Model rigid = makePuma560(false), driven = makePuma560(true);
  Data data_rigid(rigid), data_driven(driven);
  std::mt19937_64 rng(7);
  Eigen::VectorXd q = test::randomVector(rng, 6, 2.0), dq = test::randomVector(rng, 6, 2.0),
                  ddq = test::randomVector(rng, 6, 2.0);
  dq[3] = 0.0;  // at rest: no Coulomb friction and no asymmetry
  const Eigen::VectorXd difference =
      rnea(driven, data_driven, q, dq, ddq) - rnea(rigid, data_rigid, q, dq, ddq);
  for (int i = 0; i < 6; ++i) {
    const DriveParameters<double>& d = driven.drives()[i];
    const double s = dq[i] > 0 ? 1.0 : (dq[i] < 0 ? -1.0 : 0.0);
    const double expected = d[DriveTerm::kRotorInertia] * ddq[i] + d[DriveTerm::kViscous] * dq[i] +
                            d[DriveTerm::kCoulomb] * s +
                            (s != 0.0 ? d[DriveTerm::kCoulombAsymmetry] : 0.0);
    EXPECT_NEAR(difference[i], expected, 1e-12) << "joint " << i + 1;
  }
}

TEST(Rnea, RejectsMismatchedSizes) {
  const Model model = makePuma560();
  Data data(model);
  const Eigen::VectorXd six = Eigen::VectorXd::Zero(6), five = Eigen::VectorXd::Zero(5);
  try {
    rnea(model, data, six, five, six);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "dq has 5 entries, model 'puma560' has 6 joints");
  }
  const Model other = test::randomTree(1);
  Data wrong(other);
  EXPECT_THROW(rnea(model, wrong, six, six, six), InputError);
}

}  // namespace
}  // namespace dynid
