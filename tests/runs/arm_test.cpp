// The arm and its dynamics at one state (analysis/runs/arm.hpp).
#include "analysis/runs/arm.hpp"

#include <gtest/gtest.h>

#include <optional>

#include "core/errors.hpp"
#include "data/panda.hpp"
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

/// Recorded kinematics as an estimate.json keeps them: kinematicsSignature's rows.
nlohmann::json recorded(const Model& model) {
  const Eigen::MatrixXd k = kinematicsSignature(model);
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < k.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < k.cols(); ++c) row.push_back(k(i, c));
    rows.push_back(row);
  }
  return rows;
}

TEST(Arm, KinematicsDifferenceSaysWhatDiffers) {
  const Model puma = makePuma560(false);
  EXPECT_EQ(kinematicsDifference(recorded(puma), puma), "");
  // Another joint count.
  EXPECT_EQ(kinematicsDifference(recorded(puma), makePanda(false)),
            "it has 7 joints, the estimate's robot 6");
  // The first link's frame moved 0.05 m up: named, with how far.
  nlohmann::json moved = recorded(puma);
  moved[1][11] = moved[1][11].get<double>() - 0.05;
  const std::string text = kinematicsDifference(moved, puma);
  EXPECT_NE(text.find("link 2 (" + puma.link_names[1] + ")'s frame at q = 0 lies 0.05 m"),
            std::string::npos)
      << text;
  // A joint axis turned (its frame kept): the joint named.
  nlohmann::json turned = recorded(puma);
  turned[3][12] = turned[3][12].get<double>() + 0.1;
  EXPECT_NE(kinematicsDifference(turned, puma).find("joint 4 (" + puma.joint_names[3] + ")"),
            std::string::npos);
}

}  // namespace
}  // namespace dynid
