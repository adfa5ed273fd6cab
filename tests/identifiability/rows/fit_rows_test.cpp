#include "identifiability/rows/fit_rows.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/signal.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

// The reach is where the zero-phase impulse response's tails fall to kFilterReachShare of its
// absolute sum: just beyond it they hold less, just inside more.
TEST(FitRows, TheFiltersReachIsWhereItsImpulseResponseFallsToItsShare) {
  const TorqueFilter filter{4, 10.0, 1000.0};
  const int reach = filterReach(filter);
  const std::vector<Biquad> sections = butterworthLowPass(4, 10.0, 1000.0);
  const int half = 4000;
  Eigen::VectorXd h = Eigen::VectorXd::Zero(2 * half + 1);
  h[half] = 1.0;
  h = filtfilt(sections, h);
  const double total = h.cwiseAbs().sum();
  const auto beyond = [&](int r) {
    return total - h.segment(half - r, 2 * r + 1).cwiseAbs().sum();
  };
  EXPECT_LE(beyond(reach), kFilterReachShare * total);
  EXPECT_GT(beyond(reach - 1), kFilterReachShare * total);
  // A tenth of the cutoff's period or more: a 10 Hz filter spreads a step over tens of ms.
  EXPECT_GT(reach, 10);
  // A cutoff twice as high reaches about half as far (the response scales with 1 / cutoff).
  const int faster = filterReach({4, 20.0, 1000.0});
  EXPECT_NEAR(static_cast<double>(faster) / reach, 0.5, 0.1);
}

// Through the filter, a joint's Coulomb column is the filter applied to sign(dq) on its run, and
// its rows within the reach of a resting sample are left out; a sample of another run is not
// touched by the first's.
TEST(FitRows, AFilteredRunsFrictionColumnIsItsFilteredSignAndRowsNearRestAreLeftOut) {
  Model puma = makePuma560(true);
  puma.rest_velocities.assign(6, 1e-3);
  const int count = 3000, gap_at = 2000;
  Eigen::VectorXd time(count);
  Eigen::MatrixXd dq = Eigen::MatrixXd::Constant(6, count, 0.5);
  for (int k = 0; k < count; ++k) {
    time[k] = k < gap_at ? k * 1e-3 : 10.0 + k * 1e-3;  // a second run after a 10 s gap
    dq(1, k) = std::sin(2.0 * M_PI * 0.7 * time[k]);    // joint 2 reverses; the others move on
  }
  dq(3, 500) = 0.0;                             // joint 4 rests for one sample
  dq.block(4, 1200, 1, 100).setConstant(5e-3);  // joint 5 creeps
  const TorqueFilter filter{4, 10.0, 1000.0};
  const FitRows rows(puma, time, dq, filter);
  ASSERT_TRUE(rows.filtered());
  const int reach = rows.reach();
  EXPECT_EQ(reach, filterReach(filter));
  // Joint 2's Coulomb column, run by run, against filtfilt of its sign.
  const std::vector<Biquad> sections = butterworthLowPass(4, 10.0, 1000.0);
  for (const auto& [first, length] : {std::pair{0, gap_at}, std::pair{gap_at, count - gap_at}}) {
    Eigen::VectorXd sign(length);
    for (int k = 0; k < length; ++k)
      sign[k] = driveBasis(static_cast<int>(DriveTerm::kCoulomb), dq(1, first + k), 0.0, 1e-3);
    const Eigen::VectorXd filtered = filtfilt(sections, sign);
    for (int k = 0; k < length; k += 97) {
      Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(6, puma.parameterLayout().size());
      Eigen::VectorXd tau = Eigen::VectorXd::Ones(6);
      const long long s = first + k;
      rows.apply(s, dq.col(first + k), Y, tau);
      if (!rows.fitted(s, 1, dq(1, first + k))) {
        EXPECT_EQ(tau[1], 0.0);
        continue;
      }
      EXPECT_EQ(Y(1, puma.parameterLayout().driveIndex(1, DriveTerm::kCoulomb)), filtered[k]) << s;
      EXPECT_EQ(tau[1], 1.0);
    }
  }
  // Joint 4's one resting sample leaves out its rows within the reach, and no other joint's.
  EXPECT_FALSE(rows.fitted(500 - reach, 3, 0.5));
  EXPECT_FALSE(rows.fitted(500 + reach, 3, 0.5));
  EXPECT_TRUE(rows.fitted(500 - reach - 1, 3, 0.5));
  EXPECT_TRUE(rows.fitted(500 + reach + 1, 3, 0.5));
  EXPECT_TRUE(rows.fitted(500, 0, 0.5));
  // Joint 2's reversals are clean (it accelerates through zero): its rows stay, the step in its
  // friction being the filtered column's.
  EXPECT_TRUE(rows.fitted(714, 1, dq(1, 714)));
  // Joint 5 creeps at 5e-3 rad/s from 1200 to 1299 (a stick, filtered): above its rest velocity
  // but slower than kDwellSpeedShare of its RMS speed and, from 1201 to 1298, not accelerating
  // (the first and last creeping samples' central differences see the step), so left out within
  // the reach of those.
  EXPECT_FALSE(rows.fitted(1201 - reach, 4, 0.5));
  EXPECT_FALSE(rows.fitted(1298 + reach, 4, 0.5));
  EXPECT_TRUE(rows.fitted(1200 - reach, 4, 0.5));
  EXPECT_TRUE(rows.fitted(1299 + reach, 4, 0.5));
  EXPECT_TRUE(rows.fitted(500, 0, 0.5));
  // The filtered columns' correction to a model's own friction: each term's parameter times
  // its filtered value less its own (here near joint 2's first reversal, where they differ).
  Eigen::VectorXd sign(gap_at), square(gap_at);
  for (int k = 0; k < gap_at; ++k) {
    sign[k] = driveBasis(static_cast<int>(DriveTerm::kCoulomb), dq(1, k), 0.0, 1e-3);
    square[k] = sign[k] * sign[k];
  }
  const Eigen::VectorXd f_sign = filtfilt(sections, sign), f_square = filtfilt(sections, square);
  const int s = 714;  // sin(2 pi 0.7 t) crosses zero at t = 0.714 s
  const double fc = puma.drives()[1].term(static_cast<int>(DriveTerm::kCoulomb)),
               fa = puma.drives()[1].term(static_cast<int>(DriveTerm::kCoulombAsymmetry));
  const double expected = fc * (f_sign[s] - sign[s]) + fa * (f_square[s] - square[s]);
  ASSERT_GT(std::abs(f_sign[s] - sign[s]), 0.1);  // the step is spread here
  // 1e-12 relative: the same sums, taken in another order.
  EXPECT_NEAR(rows.filteredDriveCorrection(puma, s, 1, dq(1, s)), expected, 1e-12 * std::abs(fc));
  EXPECT_THROW(FitRows(puma, time.head(10), dq, filter), InputError);
  EXPECT_THROW(FitRows(puma, time, dq, TorqueFilter{}), InputError);
}

}  // namespace
}  // namespace dynid
