#include "core/kinematics.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

TEST(Kinematics, PumaAtZeroPoseMatchesTheDhTable) {
  // Standard DH at q = 0: the wrist centre sits at (a2 + a3, -d3, d4) (Robotics Toolbox
  // p560.fkine(qz) = (0.4521, -0.15005, 0.4318)).
  const Model model = makePuma560();
  Data data(model);
  forwardKinematics(model, data, Eigen::VectorXd::Zero(6));
  const Eigen::Vector3d expected(0.4318 + 0.0203, -0.15005, 0.4318);
  EXPECT_LT((data.oMi[5].translation - expected).norm(), 1e-15);
}

TEST(Kinematics, RejectsWrongSize) {
  const Model model = makePuma560();
  Data data(model);
  try {
    forwardKinematics(model, data, Eigen::VectorXd::Zero(5));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "q has 5 entries, model 'puma560' has 6 joints");
  }
}

}  // namespace
}  // namespace dynid
