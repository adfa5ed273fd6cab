// The arm and its dynamics at one state (analysis/runs/arm.hpp).
#include "analysis/runs/arm.hpp"

#include <gtest/gtest.h>

#include <optional>

#include "core/errors.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

TEST(Arm, DynamicsAtReportsASingularState) {
  const Model puma = makePuma560(false);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  const DynamicsOutcome at_rest = dynamicsAt(puma, zero, zero, std::nullopt, std::nullopt);
  // tau = g(q) and ABA inverts it: ddq = 0 for tau = g(q) (round-off of the M^-1 solve).
  const DynamicsOutcome back = dynamicsAt(puma, zero, zero, std::nullopt, at_rest.tau);
  EXPECT_LT(back.ddq.norm(), 1e-12);
  Model massless = puma;
  massless.setLinkInertia(5, RigidInertia<double>());
  EXPECT_THROW(dynamicsAt(massless, zero, zero, std::nullopt, zero), NumericalError);
}

}  // namespace
}  // namespace dynid
