#include "core/crba.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "core/energy.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Crba, PlanarTwoLinkMatchesTheTextbook) {
  const test::Planar2R arm;
  const Model model = arm.model();
  Data data(model);
  for (double q2 : {-2.0, 0.0, 0.4, 1.9}) {
    const Eigen::Vector2d q(0.3, q2);
    EXPECT_LT((crba(model, data, q) - arm.massMatrix(q)).norm(), 1e-14);
  }
}

TEST(Crba, SymmetricPositiveDefiniteAndMatchesKineticEnergy) {
  std::mt19937_64 rng(2);
  for (int seed = 0; seed < 8; ++seed) {
    const Model model =
        seed == 0 ? makePuma560(true) : test::randomTree(seed, {.drives = seed % 2 == 1});
    Data data(model);
    const int n = model.numJoints();
    const Eigen::VectorXd q = test::randomVector(rng, n, 2.0), dq = test::randomVector(rng, n, 2.0);
    const Eigen::MatrixXd M = crba(model, data, q);
    EXPECT_EQ(M, M.transpose()) << "seed " << seed;
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(M).info(), Eigen::Success) << "seed " << seed;
    // 1/2 dq^T M dq against the sum of body kinetic energies; round-off relative to the energy.
    const double energy = kineticEnergy(model, data, q, dq);
    EXPECT_NEAR(0.5 * dq.dot(M * dq), energy, 1e-12 * energy) << "seed " << seed;
  }
}

/// CRBA on `fast` and on the same model with permuted placements off, at `trials` random states:
/// the same matrix to round-off (the two paths multiply in another order: a few ulps of M's
/// entries), exactly symmetric. Returns the last matrix.
Eigen::MatrixXd expectTheGeneralMatrix(const Model& fast, std::mt19937_64& rng, int trials) {
  Model general = fast;
  general.setPermutedPlacements(false);
  Data a(fast), b(general);
  Eigen::MatrixXd M;
  for (int k = 0; k < trials; ++k) {
    const Eigen::VectorXd q = test::randomVector(rng, fast.numJoints(), 2.0);
    M = crba(fast, a, q);
    EXPECT_LT((M - crba(general, b, q)).cwiseAbs().maxCoeff(), 1e-14 * M.norm()) << fast.name;
    EXPECT_EQ(M, M.transpose());
  }
  return M;
}

// The permuted-placement path (composite inertias and forces rotated about z, then permuted) and
// the general transforms give the same matrix: the PUMA (standard DH) and the Panda (modified DH),
// with drives, at random states.
TEST(Crba, PermutedPlacementsGiveTheGeneralMatrix) {
  std::mt19937_64 rng(5);
  for (const Model& fast : {makePuma560(true), makePanda(true)})
    expectTheGeneralMatrix(fast, rng, 20);
}

// The same on trees (two roots, two children per body) with every permutation: the sweep moves a
// subtree's columns together and the roots' entries take the one-component shortcut.
TEST(Crba, PermutedTreesGiveTheGeneralMatrix) {
  std::mt19937_64 rng(7);
  for (int seed = 0; seed < 4; ++seed) {
    const Eigen::MatrixXd M =
        expectTheGeneralMatrix(test::permutedTree(200 + seed, seed % 2 == 1), rng, 5);
    // Bodies on different branches do not couple: exact zeros (joints 2 and 3 share only a
    // parent, joint 1 is the other root).
    EXPECT_EQ(M(2, 3), 0.0) << seed;
    EXPECT_EQ(M(0, 1), 0.0) << seed;
  }
}

}  // namespace
}  // namespace dynid
