// The holding contacts' forces (analysis/floating/contact_forces.hpp): the least-norm forces that
// carry a wrench, within friction cones when asked; none when the cones cannot carry it.
#include "analysis/floating/contact_forces.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/errors.hpp"
#include "core/spatial.hpp"

namespace dynid {
namespace {

/// The map of point contacts at `points` (base axes): each force f at p adds (p x f, f).
Eigen::MatrixXd pointMap(const std::vector<Eigen::Vector3d>& points) {
  Eigen::MatrixXd map(6, 3 * static_cast<int>(points.size()));
  for (std::size_t c = 0; c < points.size(); ++c) {
    map.block<3, 3>(0, 3 * static_cast<int>(c)) = skew(points[c]);
    map.block<3, 3>(3, 3 * static_cast<int>(c)).setIdentity();
  }
  return map;
}

ContactCones conesOf(int contacts, double mu) {
  ContactCones cones;
  cones.friction = mu;
  for (int c = 0; c < contacts; ++c) cones.coned.push_back(3 * c);
  return cones;
}

/// How far f's contacts are outside their cones about z (0 inside).
double excess(const Eigen::VectorXd& f, double mu) {
  double out = 0.0;
  for (Eigen::Index c = 0; c + 3 <= f.size(); c += 3)
    out = std::max({out, -f[c + 2], f.segment<2>(c).norm() - mu * f[c + 2]});
  return out;
}

TEST(ContactForces, WithoutFrictionTheyAreTheLeastNormForces) {
  const Eigen::MatrixXd map = pointMap({{0.3, 0.2, -0.5}, {-0.3, 0.2, -0.5}, {0.0, -0.3, -0.5}});
  Eigen::VectorXd wrench(6);
  wrench << 1.0, -2.0, 0.5, 3.0, -4.0, 300.0;
  const Eigen::VectorXd f = *contactForces(map, wrench, {});
  EXPECT_LT((map * f - wrench).norm(), 1e-12 * wrench.norm());
  // Least norm: no component in the map's null space.
  const Eigen::VectorXd least = map.completeOrthogonalDecomposition().solve(wrench);
  EXPECT_LT((f - least).norm(), 1e-12 * least.norm());
}

TEST(ContactForces, ALateralForceBeyondTheConeIsCarriedByNone) {
  // One contact at the origin pushed sideways as much as up: inside a cone of mu 1.5, outside 0.6.
  const Eigen::MatrixXd map = pointMap({Eigen::Vector3d::Zero()});
  Eigen::VectorXd wrench(6);
  wrench << 0.0, 0.0, 0.0, 10.0, 0.0, 10.0;
  const std::optional<Eigen::VectorXd> wide = contactForces(map, wrench, conesOf(1, 1.5));
  ASSERT_TRUE(wide.has_value());
  EXPECT_LT((*wide - wrench.tail<3>()).norm(), 1e-9 * wrench.norm());
  EXPECT_FALSE(contactForces(map, wrench, conesOf(1, 0.6)).has_value());
  // Pulling on the ground: no cone carries it.
  wrench << 0.0, 0.0, 0.0, 0.0, 0.0, -10.0;
  EXPECT_FALSE(contactForces(map, wrench, conesOf(1, 10.0)).has_value());
}

TEST(ContactForces, WithinTheConesNoOtherForcesThatCarryTheWrenchHaveALowerNorm) {
  // Four feet under a body pushed sideways and twisted: the least-norm forces leave the cones of
  // mu 0.3, so the cones bind; the answer must be feasible and no feasible point of the null
  // space, drawn at random around it, may have a lower norm (convexity: a local test suffices).
  const Eigen::MatrixXd map =
      pointMap({{0.3, 0.2, -0.5}, {-0.3, 0.2, -0.5}, {0.3, -0.2, -0.5}, {-0.3, -0.2, -0.45}});
  Eigen::VectorXd wrench(6);
  wrench << 5.0, -8.0, 6.0, 60.0, -20.0, 300.0;
  const double mu = 0.3;
  const Eigen::VectorXd least = map.completeOrthogonalDecomposition().solve(wrench);
  ASSERT_GT(excess(least, mu), 1.0);  // the cones bind
  const std::optional<Eigen::VectorXd> f = contactForces(map, wrench, conesOf(4, mu));
  ASSERT_TRUE(f.has_value());
  EXPECT_LT((map * *f - wrench).norm(), 1e-9 * wrench.norm());
  EXPECT_LT(excess(*f, mu), 1e-9 * wrench.norm());
  const Eigen::MatrixXd null = map.fullPivLu().kernel();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  int feasible = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::VectorXd step(null.cols());
    for (Eigen::Index k = 0; k < step.size(); ++k) step[k] = normal(rng);
    const Eigen::VectorXd other = *f + null * step * (trial % 2 == 0 ? 0.1 : 2.0);
    if (excess(other, mu) > 0.0) continue;
    ++feasible;
    // The solver stops at a residual of 1e-10 of the wrench: its norm within that of the optimum.
    EXPECT_GE(other.norm(), f->norm() - 1e-8 * wrench.norm());
  }
  EXPECT_GT(feasible, 100);
}

TEST(ContactForces, AFrameContactsMomentIsFreeAndItsForceConed) {
  // A sole at the origin (moment rows then force rows) carries a moment of any size, its force
  // within the cone.
  Eigen::MatrixXd map = Eigen::MatrixXd::Identity(6, 6);
  Eigen::VectorXd wrench(6);
  wrench << 40.0, -30.0, 5.0, 1.0, 2.0, 100.0;
  ContactCones cones;
  cones.friction = 0.5;
  cones.coned = {3};
  const std::optional<Eigen::VectorXd> f = contactForces(map, wrench, cones);
  ASSERT_TRUE(f.has_value());
  EXPECT_LT((*f - wrench).norm(), 1e-9 * wrench.norm());
}

TEST(ContactForces, EachConeStandsOnItsOwnAxis) {
  // One point carrying a force along x: inside a cone about x, outside every cone about z.
  const Eigen::MatrixXd map = pointMap({Eigen::Vector3d::Zero()});
  Eigen::VectorXd wrench = Eigen::VectorXd::Zero(6);
  wrench.tail<3>() << 10.0, 1.0, 0.0;
  ContactCones cones = conesOf(1, 0.5);
  EXPECT_FALSE(contactForces(map, wrench, cones).has_value());
  cones.axes = {Eigen::Vector3d::UnitX()};
  const std::optional<Eigen::VectorXd> f = contactForces(map, wrench, cones);
  ASSERT_TRUE(f.has_value());
  EXPECT_LT((*f - wrench.tail<3>()).norm(), 1e-9 * wrench.norm());
  cones.axes.push_back(Eigen::Vector3d::UnitZ());  // two axes for one cone
  EXPECT_THROW(contactForces(map, wrench, cones), InputError);
}

TEST(ContactForces, SizesThatDisagreeAreRefused) {
  const Eigen::MatrixXd map = pointMap({Eigen::Vector3d::Zero()});
  EXPECT_THROW(contactForces(map, Eigen::VectorXd::Zero(5), {}), InputError);
  EXPECT_THROW(contactForces(map.topRows(5), Eigen::VectorXd::Zero(6), {}), InputError);
  ContactCones cones = conesOf(2, 0.5);  // a second force the map does not have
  EXPECT_THROW(contactForces(map, Eigen::VectorXd::Zero(6), cones), InputError);
  cones = conesOf(1, -0.5);
  EXPECT_THROW(contactForces(map, Eigen::VectorXd::Zero(6), cones), InputError);
}

}  // namespace
}  // namespace dynid
