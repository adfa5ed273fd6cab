#include "core/perturb.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

TEST(Perturb, StaysWithinTheFractionAndKeepsZeros) {
  const Model truth = makePuma560(true);
  const Model guess = perturbedModel(truth, 0.3, 1);
  for (int i = 0; i < 6; ++i) {
    const auto p = standardToPaper(toStandardVector(truth.inertias()[i]));
    const auto g = standardToPaper(toStandardVector(guess.inertias()[i]));
    for (int k = 0; k < 7; ++k) {
      if (p(k) == 0.0) {
        EXPECT_EQ(g(k), 0.0);
        continue;
      }
      const double ratio = g(k) / p(k);
      // 1e-12: round-off of the paper <-> standard conversions.
      EXPECT_GE(ratio, 0.7 - 1e-12) << "link " << i + 1 << " parameter " << k;
      EXPECT_LE(ratio, 1.3 + 1e-12);
    }
  }
  EXPECT_NE(guess.standardParameters(), truth.standardParameters());
  EXPECT_EQ(perturbedModel(truth, 0.3, 1).standardParameters(), guess.standardParameters());
  EXPECT_NE(perturbedModel(truth, 0.3, 2).standardParameters(), guess.standardParameters());
  EXPECT_THROW(perturbedModel(truth, 1.0, 1), InputError);
  // The dynamics use the perturbed parameters (the derived joint-frame inertias are refreshed).
  Data a(truth), b(guess);
  const Eigen::VectorXd q = puma560Pose("qn"), zero = Eigen::VectorXd::Zero(6);
  const Eigen::VectorXd tau_truth = rnea(truth, a, q, zero, zero);
  EXPECT_GT((rnea(guess, b, q, zero, zero) - tau_truth).norm(), 0.01 * tau_truth.norm());
}

}  // namespace
}  // namespace dynid
