// The combined estimator's front: every point physically consistent, each from the last with pc's
// normalisers, the trade between the criteria along it, and its input checks.
#include "analysis/estimation/front.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/perturb.hpp"
#include "search/gc_error.hpp"
#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// A noisy PUMA log, pc from a prior 20 % off the truth (as a CAD model is), 8 GC segments (short
/// enough for the sanitizer run).
struct FrontCase {
  Model truth = makePuma560();
  Model prior = perturbedModel(truth, 0.2, 5);
  Trajectory data = test::pumaTrajectory(truth, 2.0, 0.5, 3);
  BaseParameters base = test::pumaBase(truth);
  Observation observation = observationFromTrajectory(truth, data);
  LeastSquaresSource source;
  LeastSquaresOutcome pc;
  GcProblem gc;

  FrontCase() {
    source.observation = &observation;
    pc = leastSquaresEstimate(Method::kPc, base, source, prior.standardParameters());
    SegmentOptions options = normalisedSegments();
    options.num_segments = 8;
    gc = makeGcProblem(data, options);
  }
};

CombinedOptions sweepOptions() {
  CombinedOptions options;
  options.max_seconds = 0.0;  // iterations bound each point: the same on any machine
  options.max_iterations = 5;
  options.noise_floor = false;  // the trade itself (this log's GC error is mostly noise)
  return options;
}

TEST(CombinedFront, EveryPointIsConsistentAndTradesTorqueFitForMotion) {
  const FrontCase s;
  ASSERT_TRUE(s.pc.pc && s.pc.pc->usable);
  const std::vector<double> weights = {0.3, 10.0};
  const std::vector<FrontPoint> front =
      combinedFront(s.truth, s.base, s.source, s.pc, s.gc, sweepOptions(), weights);
  ASSERT_EQ(front.size(), weights.size());
  const PhysicalProblem& torque = *s.pc.pc->problem;
  for (std::size_t k = 0; k < front.size(); ++k) {
    const FrontPoint& p = front[k];
    EXPECT_EQ(p.weight, weights[k]);
    // F is finite exactly inside the physical set (every pseudo-inertia positive definite).
    EXPECT_TRUE(std::isfinite(torque.cost(p.estimate.standard))) << k;
    // Every point's normaliser is pc's: G0 the first start's GC error / 2.
    EXPECT_EQ(p.detail.gc_scale, 0.5 * front.front().detail.initial_gc) << k;
    if (k == 0) continue;
    // Each point starts where the last ended and only improves its own cost there.
    const FrontPoint& last = front[k - 1];
    EXPECT_EQ(p.detail.initial_gc, last.detail.final_gc) << k;
    EXPECT_LE(p.detail.final_cost, p.detail.initial_cost) << k;
  }
  // The first point starts at pc, the minimiser of the torque term; along the front the motion
  // is predicted better and the torques fitted worse.
  Model at_pc = s.truth;
  at_pc.setStandardParameters(s.pc.standard);
  ThreadPool pool(1);
  GcWorkspace workspace(1);
  EXPECT_EQ(front.front().detail.initial_gc, gcError(at_pc, s.gc, workspace, pool));
  EXPECT_LT(front.back().detail.final_gc, front.front().detail.initial_gc);
  EXPECT_LT(front.back().detail.final_gc, front.front().detail.final_gc);
  EXPECT_GT(front.back().detail.final_torque, front.front().detail.final_torque);
  // The first point is the combined estimate from pc at its weight: the same computation.
  CombinedOptions one = sweepOptions();
  one.gc_weight = weights[0];
  CombinedResult detail;
  const LeastSquaresOutcome direct =
      combinedEstimate(s.truth, s.base, s.source, s.pc, s.gc, one, &detail);
  EXPECT_EQ(direct.standard, front.front().estimate.standard);
}

TEST(CombinedFront, RefusesWeightsThatAreNotASweep) {
  const FrontCase s;
  for (const std::vector<double>& weights :
       {std::vector<double>{}, {0.0, 1.0}, {1.0, 1.0}, {3.0, 1.0}, {1.0, INFINITY}}) {
    try {
      combinedFront(s.truth, s.base, s.source, s.pc, s.gc, sweepOptions(), weights);
      FAIL() << "took " << weights.size() << " weights";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("`front_weights`"), std::string::npos) << e.what();
    }
  }
  CombinedOptions bad = sweepOptions();
  bad.given_gc = std::nan("");
  EXPECT_THROW(combinedFront(s.truth, s.base, s.source, s.pc, s.gc, bad, {1.0}), InputError);
}

// The choice: the torque bound first, then the GC error above each candidate's noise floor, the
// torque error among those at their floors.
TEST(ChooseByHeldOut, TakesTheLeastGcAboveTheNoiseFloorWithinTheTorqueBound) {
  // Without floors: the least GC error within 5 % of the best torque error (1.0): 1.04 and 61.
  std::vector<HeldOutErrors> c = {{1.00, 1000.0}, {1.04, 61.0}, {1.10, 10.0}};
  FrontChoice choice = chooseByHeldOut(c, 0.05);
  EXPECT_EQ(choice.best_torque, 0);
  EXPECT_DOUBLE_EQ(choice.torque_bound, 1.05);
  EXPECT_EQ(choice.index, 1);
  EXPECT_FALSE(choice.at_floor);
  // Inconsistent or not finite: never a candidate, nor the bound's.
  c[0].consistent = false;
  c[1].gc = std::nan("");
  EXPECT_EQ(chooseByHeldOut(c, 0.05).index, 2);
  // A simulated log's case: every GC error at its own floor (the truth 1791 at 1809, the input
  // model 1479 at 1566, pc 3199 at 3125): the motion cannot tell them apart, the torques decide.
  c = {{0.0417, 3199.0, true, 3125.0},
       {0.0417, 1791.0, true, 1809.0},
       {0.0418, 1479.0, true, 1566.0}};
  choice = chooseByHeldOut(c, 0.05);
  EXPECT_EQ(choice.index, 0);  // the least torque error (ties: the earlier)
  EXPECT_TRUE(choice.at_floor);
  // Above the floors, the excess decides, not the raw GC error: 100 over a floor of 50 beats 80
  // over a floor of 5 (a model that damps the noise more is not a better model for that).
  c = {{0.01, 80.0, true, 5.0}, {0.01, 100.0, true, 50.0}};
  EXPECT_EQ(chooseByHeldOut(c, 0.05).index, 1);
  EXPECT_DOUBLE_EQ(c[0].gcExcess(), 75.0);
  EXPECT_DOUBLE_EQ(HeldOutErrors({0.01, 54.9, true, 50.0}).gcExcess(), 0.0);  // within 10 %
  // Nothing usable: no choice.
  EXPECT_EQ(chooseByHeldOut({{std::nan(""), 1.0}}, 0.05).index, -1);
}

}  // namespace
}  // namespace dynid
