// Built with the core sources compiled under EIGEN_RUNTIME_NO_MALLOC (tests/CMakeLists.txt): once a
// Data exists, RNEA, CRBA, ABA, forward kinematics and the integrator steps allocate nothing, or
// Eigen's assertion aborts the test.
#include <gtest/gtest.h>

#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/integrators.hpp"
#include "core/kinematics.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

class NoMalloc : public ::testing::Test {
 protected:
  void TearDown() override { Eigen::internal::set_is_malloc_allowed(true); }
};

TEST_F(NoMalloc, CheckIsActive) {
  // The mechanism itself: allocating a dynamic vector while disallowed aborts.
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::VectorXd x(100);
        x.setZero();
      },
      "");
}

TEST_F(NoMalloc, AlgorithmsAllocateNothing) {
  for (bool drives : {false, true}) {
    const Model model = makePuma560(drives);
    Data data(model);
    Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.3),
                    ddq = Eigen::VectorXd::Constant(6, -0.2),
                    tau = Eigen::VectorXd::Constant(6, 1.0);
    Eigen::internal::set_is_malloc_allowed(false);
    rnea(model, data, q, dq, ddq);
    crba(model, data, q);
    aba(model, data, q, dq, tau);
    forwardKinematics(model, data, q);
    rk4Step(model, data, q, dq, tau, 1e-3);
    semiImplicitEulerStep(model, data, q, dq, tau, 1e-3);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_TRUE(q.allFinite());
  }
}

}  // namespace
}  // namespace dynid
