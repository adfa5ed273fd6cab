#include "core/drive_terms.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>

#include "core/aba.hpp"
#include "core/errors.hpp"
#include "core/friction.hpp"
#include "core/parameters.hpp"
#include "core/rnea.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(DriveTerms, EveryRowParsesPrintsAndIsNamedOnce) {
  std::set<std::string_view> keys, names;
  for (int k = 0; k < kDriveTermCount; ++k) {
    const DriveTermInfo& row = kDriveTermTable[k];
    EXPECT_TRUE(keys.insert(row.key).second) << row.key;
    EXPECT_TRUE(names.insert(row.name).second) << row.name;
    const DriveTerms one = parseDriveTerms(row.key);
    EXPECT_EQ(one, DriveTerms::of({row.term}));
    EXPECT_EQ(driveTermsText(one), row.key);
    EXPECT_NE(driveTermHelp().find(std::string(row.key) + " "), std::string::npos) << row.key;
    const ParameterLayout layout{2, one};
    EXPECT_EQ(standardParameterNames(layout)[layout.driveIndex(1, k)], std::string(row.name) + "2");
  }
  EXPECT_EQ(parseDriveTerms(driveTermsText(DriveTerms{(1u << kDriveTermCount) - 1})).count(),
            kDriveTermCount);
}

TEST(DriveTerms, StribeckColumnIsSignTimesGaussianOfVelocity) {
  // Fs sign(dq) exp(-(dq/vs)^2) with vs = kStribeckVelocity: closed forms at 0, vs and -2 vs.
  const int k = static_cast<int>(DriveTerm::kStribeck);
  const double vs = kStribeckVelocity;
  EXPECT_EQ(driveBasis(k, 0.0, 5.0), 0.0);
  EXPECT_DOUBLE_EQ(driveBasis(k, vs, 5.0), std::exp(-1.0));
  EXPECT_DOUBLE_EQ(driveBasis(k, -2.0 * vs, 5.0), -std::exp(-4.0));
  EXPECT_LT(std::abs(driveBasis(k, 20.0 * vs, 0.0)), 1e-150);  // gone at speed: exp(-400)
  // Its derivative in dq through ceres::Jet: -2 dq / vs^2 exp(-(dq/vs)^2) for dq > 0.
  using Jet = ceres::Jet<double, 1>;
  const double dq = 0.7 * vs;
  const Jet phi = driveBasis(k, Jet(dq, 0), Jet(0.0));
  EXPECT_DOUBLE_EQ(phi.v[0], -2.0 * dq / (vs * vs) * std::exp(-(dq / vs) * (dq / vs)));
  // The pc estimator keeps it non-negative; perturbation draws it only when the model has it.
  EXPECT_TRUE(kDriveTermTable[k].non_negative);
  EXPECT_EQ(kDriveTermTable[k].draw, DriveTermInfo::Draw::kWhenEnabled);
}

TEST(DriveTerms, TorqueIsTheSumOfParameterTimesColumnForEverySubset) {
  // driveTorque, jointFriction and driveInertia against sum_k theta_k phi_k(dq, ddq) written out
  // from the table, for every subset and at rest (dq = 0).
  Model model = test::randomTree(41, {.num_bodies = 3, .drives = true});
  std::mt19937_64 rng(41);
  for (unsigned mask = 0; mask < (1u << kDriveTermCount); ++mask) {
    model.setDriveTerms(DriveTerms{mask});
    for (double dq : {0.0, 0.03, -0.4, 2.0}) {
      const double ddq = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
      const DriveParameters<double>& d = model.drives()[1];
      double expected = 0.0, inertia = 0.0;
      for (int k = 0; k < kDriveTermCount; ++k) {
        if (!(mask >> k & 1u)) continue;
        expected += d.term(k) * driveBasis(k, dq, ddq);
        if (kDriveTermTable[k].inertial) inertia += d.term(k);
      }
      // Round-off of a sum of six terms of order 1.
      EXPECT_NEAR(driveTorque(model, 1, dq, ddq), expected, 1e-14) << mask << " " << dq;
      EXPECT_NEAR(jointFriction(model, 1, dq) + driveInertia(model, 1) * ddq, expected, 1e-14);
      EXPECT_EQ(driveInertia(model, 1), inertia);
    }
  }
}

TEST(DriveTerms, StribeckFrictionRoundTripsThroughForwardDynamics) {
  // ABA inverts RNEA with only the Stribeck term acting, at velocities around vs.
  Model model = test::randomTree(43, {.num_bodies = 4, .drives = true});
  model.setDriveTerms(DriveTerms::of({DriveTerm::kStribeck}));
  Data data(model);
  std::mt19937_64 rng(43);
  const Eigen::VectorXd q = test::randomVector(rng, 4, 2.0), ddq = test::randomVector(rng, 4, 2.0);
  const Eigen::VectorXd dq = test::randomVector(rng, 4, 2.0 * kStribeckVelocity);
  const Eigen::VectorXd tau = rnea(model, data, q, dq, ddq);
  // Round-off of ABA against RNEA on accelerations of order 1.
  EXPECT_LT((aba(model, data, q, dq, tau) - ddq).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(DriveTerms, DataBuiltBeforeTheTermsChangedIsRefused) {
  Model model = test::randomTree(47, {.num_bodies = 3, .drives = true});
  model.setDriveTerms(DriveTerms::none());
  Data data(model);
  model.setDriveTerms(DriveTerms::of({DriveTerm::kViscous}));
  const Eigen::VectorXd z = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(rnea(model, data, z, z, z), InputError);
  Data fresh(model);
  EXPECT_NO_THROW(rnea(model, fresh, z, z, z));
}

TEST(DriveTerms, SignedTermsAreTheOnesWhoseBasisJumpsAtZeroVelocity) {
  // The table's signed_by_velocity column is what driveBasis does: a term needs sign(dq) exactly
  // when its basis differs on the two sides of dq = 0.
  const double tiny = std::numeric_limits<double>::min();
  for (int k = 0; k < kDriveTermCount; ++k) {
    // A jump of order one (sign(dq) is +-1 on either side), not Fv dq's +-2e-308.
    const bool jumps = std::abs(driveBasis(k, -tiny, 0.0) - driveBasis(k, tiny, 0.0)) > 0.5 ||
                       std::abs(driveBasis(k, tiny, 0.0) - driveBasis(k, 0.0, 0.0)) > 0.5;
    EXPECT_EQ(kDriveTermTable[k].signed_by_velocity, jumps) << kDriveTermTable[k].key;
  }
}

TEST(DriveTerms, WithinTheRestVelocityTheSignedTermsAreZeroAndOutsideUnchanged) {
  const double rest = 1e-3;
  for (int k = 0; k < kDriveTermCount; ++k) {
    for (double dq : {-5e-4, 0.0, 1e-3, -1e-3, 9.99e-4}) {
      const double inside = driveBasis(k, dq, 2.0, rest);
      if (kDriveTermTable[k].signed_by_velocity)
        EXPECT_EQ(inside, 0.0) << kDriveTermTable[k].key << " " << dq;
      else
        EXPECT_EQ(inside, driveBasis(k, dq, 2.0)) << kDriveTermTable[k].key << " " << dq;
    }
    for (double dq : {-2e-3, 1.0001e-3, 0.3})
      EXPECT_EQ(driveBasis(k, dq, 2.0, rest), driveBasis(k, dq, 2.0)) << kDriveTermTable[k].key;
  }
  // rest = 0 is sign(0) = 0 exactly as before.
  EXPECT_EQ(signOutside(0.0, 0.0), 0.0);
  EXPECT_EQ(signOutside(-1e-300, 0.0), -1.0);
}

TEST(DriveTerms, StaticFrictionBandSpansTheOneSidedLimitsAndZero) {
  Model model = test::Planar2R{}.model();
  model.setDriveTerms(
      DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb, DriveTerm::kCoulombAsymmetry,
                      DriveTerm::kStribeck, DriveTerm::kOffset}));
  DriveParameters<double> d;
  d[DriveTerm::kViscous] = 0.7;  // no static part: Fv dq -> 0
  d[DriveTerm::kCoulomb] = 2.0;
  d[DriveTerm::kCoulombAsymmetry] = 0.5;
  d[DriveTerm::kStribeck] = 1.0;
  d[DriveTerm::kOffset] = 4.0;  // not friction: it acts at rest as everywhere
  model.setDrive(0, d);
  const auto [lo, hi] = staticFrictionBand(model, 0);
  EXPECT_DOUBLE_EQ(lo, -2.0 + 0.5 - 1.0);                // dq -> 0-: -Fc + Fa - Fs
  EXPECT_DOUBLE_EQ(hi, 2.0 + 0.5 + 1.0);                 // dq -> 0+: Fc + Fa + Fs
  const auto [lo2, hi2] = staticFrictionBand(model, 1);  // no friction: the band is {0}
  EXPECT_EQ(lo2, 0.0);
  EXPECT_EQ(hi2, 0.0);
  // At rest the model's friction is the offset alone; just outside, Coulomb's full level.
  model.rest_velocities = {1e-3, 1e-3};
  EXPECT_DOUBLE_EQ(jointFriction(model, 0, 5e-4), 4.0 + 0.7 * 5e-4);
  EXPECT_GT(jointFriction(model, 0, 2e-3), 4.0 + 2.0);
}

}  // namespace
}  // namespace dynid
