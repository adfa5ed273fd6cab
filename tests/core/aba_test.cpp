#include "core/aba.hpp"

#include <gtest/gtest.h>
#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "core/crba.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// A random state (q and dq within 2, ddq within 3) and the torques rnea gives for it.
struct Sample {
  Eigen::VectorXd q, dq, ddq, tau;
};
Sample randomSample(const Model& model, Data& data, std::mt19937_64& rng) {
  const int n = model.numJoints();
  Sample out{test::randomVector(rng, n, 2.0),
             test::randomVector(rng, n, 2.0),
             test::randomVector(rng, n, 3.0),
             {}};
  out.tau = rnea(model, data, out.q, out.dq, out.ddq);
  return out;
}

TEST(Aba, InvertsRnea) {
  std::mt19937_64 rng(3);
  for (int seed = 0; seed < 10; ++seed) {
    const Model model =
        seed < 2 ? makePuma560(seed == 1) : test::randomTree(seed, {.drives = seed % 2 == 1});
    Data data(model);
    for (int trial = 0; trial < 5; ++trial) {
      const auto [q, dq, ddq, tau] = randomSample(model, data, rng);
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

TEST(Aba, PermutedPlacementsAgreeWithTheGeneralPath) {
  std::mt19937_64 rng(5);
  for (int seed = 0; seed < 4; ++seed) {
    const Model model = test::permutedTree(100 + seed, seed % 2 == 1);
    // Every permutation is taken, so each of the six compiled transforms is exercised.
    for (int i = 0; i < model.numJoints(); ++i)
      ASSERT_EQ(model.placement_permutation()[i], i % 6) << seed << "/" << i;
    Model general = model;
    general.setPermutedPlacements(false);
    Data data(model), data_general(general);
    for (int trial = 0; trial < 5; ++trial) {
      const auto [q, dq, ddq, tau] = randomSample(model, data, rng);
      const Eigen::VectorXd permuted = aba(model, data, q, dq, tau);
      // The two paths round differently; both are a few ulps of the O(10) accelerations.
      EXPECT_LT((permuted - aba(general, data_general, q, dq, tau)).norm(),
                1e-12 * (1 + ddq.norm()))
          << seed << "/" << trial;
      // Against the independent inverse dynamics: the inertias span 1e-3..5, hence 1e-9.
      EXPECT_LT((permuted - ddq).norm(), 1e-9) << seed << "/" << trial;
    }
  }
}

}  // namespace
}  // namespace dynid
