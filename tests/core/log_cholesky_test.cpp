#include "core/log_cholesky.hpp"

#include <random>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(LogCholesky, RoundTripsEveryConsistentBody) {
  // The PUMA's links and random consistent bodies: standard -> phi -> standard.
  // Random consistent bodies, and the PUMA's links 2, 4, 5, 6 (link 1 is massless and link 3
  // breaks the triangle inequality: neither has a positive definite pseudo-inertia).
  std::vector<Eigen::Matrix<double, 10, 1>> bodies;
  for (int i : {1, 3, 4, 5}) bodies.push_back(toStandardVector(makePuma560().inertias()[i]));
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Model tree = test::randomTree(seed, {.num_bodies = 3});
    for (const auto& inertia : tree.inertias()) bodies.push_back(toStandardVector(inertia));
  }
  for (const auto& p : bodies) {
    const Eigen::Matrix<double, 10, 1> phi = standardToLogCholesky(p);
    const Eigen::Matrix<double, 10, 1> back = logCholeskyToStandard(phi.data());
    // Cholesky and exp/log lose a few ulps of the largest entry.
    EXPECT_LT((back - p).cwiseAbs().maxCoeff(), 1e-13 * p.cwiseAbs().maxCoeff()) << p.transpose();
  }
}

TEST(LogCholesky, EveryPhiIsPhysicallyConsistent) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 0.5);
  for (int trial = 0; trial < 500; ++trial) {
    Eigen::Matrix<double, 10, 1> phi;
    for (double& e : phi) e = normal(rng);
    const Eigen::Matrix<double, 10, 1> p = logCholeskyToStandard(phi.data());
    EXPECT_TRUE(checkPhysicalConsistency(fromStandardVector(p), 0, "body", 1e-9).empty())
        << phi.transpose();
    // And the inverse recovers phi (J = U U^T has a unique factor with a positive diagonal).
    // Round-off of J = U U^T and its Cholesky factor, relative to phi's scale.
    EXPECT_LT((standardToLogCholesky(p) - phi).cwiseAbs().maxCoeff(), 1e-10);
  }
}

TEST(LogCholesky, NearestConsistentRepairsOnlyWhatIsBroken) {
  const Eigen::Matrix<double, 10, 1> p = toStandardVector(makePuma560().inertias()[1]);
  EXPECT_EQ(nearestConsistent(p), p);
  // A negative principal moment about the centre of mass: repaired, and close.
  Eigen::Matrix<double, 10, 1> broken = p;
  broken[9] -= 0.2;  // Izz about the origin well below what the mass distribution allows
  ASSERT_FALSE(checkPhysicalConsistency(fromStandardVector(broken), 0, "l").empty());
  const Eigen::Matrix<double, 10, 1> fixed = nearestConsistent(broken);
  // The PUMA's link 3 violates the triangle inequality: repaired too.
  const Eigen::Matrix<double, 10, 1> link3 = toStandardVector(makePuma560().inertias()[2]);
  EXPECT_TRUE(
      checkPhysicalConsistency(fromStandardVector(nearestConsistent(link3)), 2, "l", 1e-9).empty());
  EXPECT_TRUE(checkPhysicalConsistency(fromStandardVector(fixed), 0, "l", 1e-9).empty());
  EXPECT_NO_THROW(standardToLogCholesky(fixed));
  EXPECT_LT((fixed - broken).norm(), 0.3);
  EXPECT_THROW(standardToLogCholesky(broken), NumericalError);
}

}  // namespace
}  // namespace dynid
