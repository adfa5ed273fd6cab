#include "core/aba.hpp"

#include <gtest/gtest.h>
#include <Eigen/Cholesky>

#include "core/crba.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Aba, InvertsRnea) {
  std::mt19937_64 rng(3);
  for (int seed = 0; seed < 10; ++seed) {
    const Model model =
        seed < 2 ? makePuma560(seed == 1) : test::randomTree(seed, {.drives = seed % 2 == 1});
    Data data(model);
    const int n = model.numJoints();
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = test::randomVector(rng, n, 2.0),
                            dq = test::randomVector(rng, n, 2.0),
                            ddq = test::randomVector(rng, n, 3.0);
      const Eigen::VectorXd tau = rnea(model, data, q, dq, ddq);
      // Accelerations of order 1 rad/s^2; the PUMA's wrist inertias (1e-4 kg m^2) against its
      // base (3 kg m^2) cost a few digits, hence 1e-9.
      EXPECT_LT((aba(model, data, q, dq, tau) - ddq).norm(), 1e-9) << seed << "/" << trial;
    }
  }
}

TEST(Aba, EqualsInverseMassMatrixTimesForce) {
  const Model model = test::randomTree(42, {.drives = true});
  Data data(model);
  std::mt19937_64 rng(4);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 2.0), dq = test::randomVector(rng, n, 2.0),
                        tau = test::randomVector(rng, n, 5.0);
  const Eigen::VectorXd bias = rnea(model, data, q, dq, Eigen::VectorXd::Zero(n));
  const Eigen::VectorXd expected = crba(model, data, q).ldlt().solve(tau - bias);
  EXPECT_LT((aba(model, data, q, dq, tau) - expected).norm(), 1e-10 * (1.0 + expected.norm()));
}

}  // namespace
}  // namespace dynid
