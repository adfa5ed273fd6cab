#include "core/energy.hpp"

#include <gtest/gtest.h>

#include "core/rnea.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Energy, PotentialGradientIsTheGravityTorque) {
  const Model model = test::randomTree(8);
  Data data(model);
  std::mt19937_64 rng(5);
  const int n = model.numJoints();
  const Eigen::VectorXd q = test::randomVector(rng, n, 1.5), zero = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd gravity = rnea(model, data, q, zero, zero);
  const double h = 1e-6;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += h, qm[i] -= h;
    const double gradient =
        (potentialEnergy(model, data, qp) - potentialEnergy(model, data, qm)) / (2 * h);
    // Central difference: truncation O(h^2) ~ 1e-12, cancellation ~ 1e-16 * 50 J / 1e-6 ~ 1e-8.
    EXPECT_NEAR(gradient, gravity[i], 1e-7) << "joint " << i;
  }
}

}  // namespace
}  // namespace dynid
