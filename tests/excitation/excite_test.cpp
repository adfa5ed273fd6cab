#include "analysis/excitation/excite.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

ExciteRequest pumaRequest(int starts, int evaluations) {
  ExciteRequest r;
  r.robot = makePuma560(false);
  r.limits = excitationLimits(r.robot, {});
  r.starts = starts;
  r.evaluations = evaluations;
  r.seed = 7;
  r.gc_segments =
      10;  // the exact GC Jacobian is the slow part of scoring: 10 segments suffice here
  return r;
}

TEST(Excite, TheSampledDesignIsItsOwnDerivativeAndAtRestAtBothEnds) {
  const Model puma = makePuma560(false);
  FourierSeries d;
  d.period = 4.0;
  d.offset = Eigen::VectorXd::LinSpaced(6, -0.3, 0.3);
  d.a = Eigen::MatrixXd::Random(6, 3);
  d.b = Eigen::MatrixXd::Random(6, 3);
  // Rest at t = 0: sum_k a_k = 0 and sum_k k b_k = 0.
  d.a.col(2) = -d.a.col(0) - d.a.col(1);
  d.b.col(2) = -(d.b.col(0) + 2.0 * d.b.col(1)) / 3.0;
  const double rate = 2000.0;
  const Trajectory t = sampleFourier(d, puma, rate);
  ASSERT_EQ(t.numSamples(), 8001);
  EXPECT_DOUBLE_EQ(t.time[t.numSamples() - 1], 4.0);
  // Central differences of a smooth motion: error (h^2/6) max|q'''| ~ 1e-7 at h = 0.5 ms.
  for (int k = 1; k + 1 < t.numSamples(); k += 397) {
    const Eigen::VectorXd dq = (t.q.col(k + 1) - t.q.col(k - 1)) * rate / 2.0;
    const Eigen::VectorXd ddq = (t.dq.col(k + 1) - t.dq.col(k - 1)) * rate / 2.0;
    EXPECT_LT((dq - t.dq.col(k)).cwiseAbs().maxCoeff(), 1e-5) << k;
    EXPECT_LT((ddq - t.ddq.col(k)).cwiseAbs().maxCoeff(), 1e-4) << k;
  }
  // 1e-12: round-off of a sum of a few O(1) terms.
  for (int k : {0, t.numSamples() - 1}) {
    EXPECT_LT(t.dq.col(k).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(t.ddq.col(k).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_LT((t.q.col(0) - t.q.col(t.numSamples() - 1)).cwiseAbs().maxCoeff(), 1e-12);
  Data data(puma);
  EXPECT_LT((t.tau.col(100) - rnea(puma, data, t.q.col(100), t.dq.col(100), t.ddq.col(100)))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  // The controller reference is the same motion.
  Eigen::VectorXd q(6), dq(6), ddq(6);
  evaluateReference(d, t.time[1234], q, dq, ddq);
  EXPECT_LT((q - t.q.col(1234)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((ddq - t.ddq.col(1234)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Excite, APumaDesignBeatsTheDefaultSinusoidWithinItsLimits) {
  ExciteRequest r = pumaRequest(2, 1500);
  r.threads = 2;
  const ExciteOutcome o = exciteRun(r);
  ASSERT_GE(o.best_start, 0);
  // The design's target: the unit-column condition number at most a third of the sinusoid's.
  EXPECT_LE(o.score.condition_unit, o.baseline.condition_unit / 3.0)
      << o.score.condition_unit << " vs " << o.baseline.condition_unit;
  EXPECT_TRUE(o.check.violations.empty());
  // Independently of checkLimits: every limit holds at 5 kHz, 5x the check's rate.
  const Trajectory fine = sampleFourier(o.design, r.robot, 5000.0);
  for (int j = 0; j < 6; ++j) {
    EXPECT_GE(fine.q.row(j).minCoeff(), r.limits.q_min[j]) << j;
    EXPECT_LE(fine.q.row(j).maxCoeff(), r.limits.q_max[j]) << j;
    EXPECT_LE(fine.dq.row(j).cwiseAbs().maxCoeff(), r.limits.dq_max[j]) << j;
    EXPECT_LE(fine.ddq.row(j).cwiseAbs().maxCoeff(), r.limits.ddq_max[j]) << j;
  }
  // The velocity or acceleration limit binds on some joint: the optimiser uses the room it has.
  double used = 0.0;
  for (int j = 0; j < 6; ++j)
    used = std::max({used, fine.dq.row(j).cwiseAbs().maxCoeff() / r.limits.dq_max[j],
                     fine.ddq.row(j).cwiseAbs().maxCoeff() / r.limits.ddq_max[j]});
  EXPECT_GT(used, 0.9);
  // Every base parameter is better determined than by the sinusoid (expected std dev).
  EXPECT_LT(o.score.std_dev.maxCoeff(), o.baseline.std_dev.maxCoeff());
}

TEST(Excite, TheSameSeedGivesTheSameDesignWithAnyThreadCount) {
  // Short starts on a short period, a coarse check: equality, not quality, is tested here (and
  // the test stays short under the sanitizers, where a regressor costs 100x more).
  ExciteRequest r = pumaRequest(2, 40);
  r.period = 4.0;
  r.check_rate = 100.0;
  r.threads = 1;
  const ExciteOutcome one = exciteRun(r);
  r.threads = 2;
  const ExciteOutcome two = exciteRun(r);
  EXPECT_EQ(one.design.a, two.design.a);
  EXPECT_EQ(one.design.b, two.design.b);
  EXPECT_EQ(one.design.offset, two.design.offset);
  EXPECT_EQ(one.best_start, two.best_start);
  r.seed = 8;
  EXPECT_NE(exciteRun(r).design.a, one.design.a);
}

TEST(Excite, TheFirstOrderGcCriterionTracksTheExactGcJacobian) {
  // The GC residuals' Jacobian over 0.05 s segments is, to first order in the horizon, the
  // time-integral of M^-1 W1 along each segment: their unit-column condition numbers agree
  // (measured within 1 % on these motions; 5 % allowed for the second-order terms).
  ExciteRequest r = pumaRequest(1, 300);
  r.criterion = ExcitationCriterion::kGc;
  r.gc_segments = 40;
  const ExciteOutcome o = exciteRun(r);
  EXPECT_NEAR(o.gc_first_order / o.gc, 1.0, 0.05) << o.gc_first_order << " vs " << o.gc;
  EXPECT_NEAR(o.baseline_gc_first_order / o.baseline_gc, 1.0, 0.05)
      << o.baseline_gc_first_order << " vs " << o.baseline_gc;
  EXPECT_LT(o.gc, o.baseline_gc / 10.0);  // the design sees every base parameter far better
}

TEST(Excite, TorqueAndFloorLimitsAreKept) {
  ExciteRequest r = pumaRequest(2, 400);
  LimitOverrides o;
  o.tau_max = Eigen::VectorXd::Constant(6, 120.0);
  o.floor = 0.0;  // link origins above the shoulder's base plane
  r.limits = excitationLimits(r.robot, o);
  const ExciteOutcome out = exciteRun(r);
  const Trajectory fine = sampleFourier(out.design, r.robot, 2000.0);
  EXPECT_LE(fine.tau.cwiseAbs().maxCoeff(), 0.9 * 120.0);
  EXPECT_GE(out.check.lowest_origin, 0.0);
}

TEST(Excite, TheRelativeSdCriterionLowersTheExpectedRelativeError) {
  // Designed for the RMS of sigma_j / |beta_j| (what the paper's base-parameter error measures).
  // The criterion has many local minima (the default run's 8 starts end a factor 3 apart), and
  // which one 3 starts reach moves with the last bits of libm's sin/cos (glibc picks its FMA
  // versions on CPUs that have FMA): seeds 1-8, with and without them (GLIBC_TUNABLES=
  // glibc.cpu.hwcaps=-FMA), ended at 0.30-0.74 of the sinusoid's 0.906 (the unit-column cond
  // criterion, same seeds: 0.57-1.11). Asserted: below 0.8 of the sinusoid's.
  ExciteRequest r = pumaRequest(3, 2000);
  r.seed = 1;
  r.criterion = ExcitationCriterion::kRelativeSd;
  const ExciteOutcome relative = exciteRun(r);
  EXPECT_LT(relative.score.relative_rms, 0.8 * relative.baseline.relative_rms)
      << relative.score.relative_rms << " vs " << relative.baseline.relative_rms;
}

// Starts left at 0: 8, and 16 for a payload motion, whose d-optimal criterion has many local
// optima (8 starts of the Panda's ended a factor 1.7 apart in log det per row from seed to seed).
TEST(Excite, UnsetStartsAreEightOrSixteenForAPayloadMotion) {
  ExciteRequest r = pumaRequest(0, 30);
  r.period = 4.0;
  r.threads = 2;
  EXPECT_EQ(exciteRun(r).starts.size(), static_cast<std::size_t>(kDefaultStarts));
  r.payload_link = 5;
  r.criterion = ExcitationCriterion::kDOptimal;
  EXPECT_EQ(exciteRun(r).starts.size(), static_cast<std::size_t>(kPayloadStarts));
  r.starts = 3;
  EXPECT_EQ(exciteRun(r).starts.size(), 3u);
  r.starts = -1;
  EXPECT_THROW(exciteRun(r), InputError);
}

TEST(Excite, ImpossibleSettingsAreRefusedWithTheReason) {
  ExciteRequest r = pumaRequest(1, 50);
  r.harmonics = 1;
  EXPECT_THROW(exciteRun(r), InputError);
  r = pumaRequest(1, 50);
  r.period = 0.0;
  EXPECT_THROW(exciteRun(r), InputError);
  r = pumaRequest(1, 50);
  r.offset = Eigen::VectorXd::Constant(6, 10.0);  // outside every position range
  EXPECT_THROW(exciteRun(r), InputError);
  // A floor above the robot: no start can meet it, and the message says which limit.
  r = pumaRequest(1, 50);
  LimitOverrides o;
  o.floor = 5.0;
  r.limits = excitationLimits(r.robot, o);
  try {
    exciteRun(r);
    FAIL() << "a floor 5 m up was met";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("floor"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseExcitationCriterion("gc-typo"), InputError);
  EXPECT_EQ(parseExcitationCriterion("d-optimal"), ExcitationCriterion::kDOptimal);
  EXPECT_EQ(parseExcitationCriterion("relative-sd"), ExcitationCriterion::kRelativeSd);
}

}  // namespace
}  // namespace dynid
