#include "search/gc_error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "core/lanes.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "search/gc_lanes_simd.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(GcError, ZeroAtTheTruthPositiveElsewhere) {
  const Model truth = makePuma560();
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(), {});
  EXPECT_EQ(problem.numSegments(), 100);
  EXPECT_EQ(problem.samples_per_segment, 50);
  ThreadPool pool(1);
  GcWorkspace workspace(1);
  // Same integrator, step and held torques as the recording: the scalar path's replay is bit for
  // bit; the lanes' differs by round-off only (gc_error.hpp: state differences below 1e-13, so a
  // squared sum below 1e-24).
  GcWorkspace scalar(1, 1);
  EXPECT_EQ(gcError(truth, problem, scalar, pool), 0.0);
  EXPECT_LT(gcError(truth, problem, workspace, pool), 1e-24);
  const double perturbed = gcError(perturbedModel(truth, 0.3, 1), problem, workspace, pool);
  EXPECT_GT(perturbed, 1e-6);
  // The paper's eq. (2): the sum of the per-segment squared state errors.
  EXPECT_DOUBLE_EQ(perturbed, workspace.segment_errors.sum());
}

TEST(GcError, SameResultForAnyThreadCount) {
  const Model guess = perturbedModel(makePuma560(), 0.3, 2);
  const GcProblem problem =
      makeGcProblem(test::pumaSearchTrajectory(), {.horizon = 0.02, .num_segments = 37});
  ThreadPool one(1), two(2);
  GcWorkspace w1(1), w2(2);
  EXPECT_EQ(gcError(guess, problem, w1, one), gcError(guess, problem, w2, two));
  // The same workspaces, and one model object changed between evaluations as an optimiser does:
  // every thread must see each evaluation's candidate (the second thread reads a copy).
  Model candidate = guess;
  for (std::uint64_t seed : {3, 4, 5}) {
    candidate.setStandardParameters(perturbedModel(makePuma560(), 0.3, seed).standardParameters());
    const double single = gcError(candidate, problem, w1, one);
    EXPECT_EQ(gcError(candidate, problem, w2, two), single) << seed;
    EXPECT_NE(single, gcError(guess, problem, w1, one)) << seed;
  }
}

// Lanes (core/lanes.hpp) roll several segments at once; each segment's error is the scalar path's
// to 1e-12 relative (gc_error.hpp gives the reason), the same for every lane width, thread count
// and instruction set 4 lanes roll in (the build's, and AVX2 and AVX-512 where this build
// dispatches to them and the CPU has them: search/gc_lanes_simd.hpp).
TEST(GcError, LanesGiveTheScalarPathsSegmentErrors) {
  const GcProblem problem =
      makeGcProblem(test::pumaSearchTrajectory(), {.num_segments = 37});  // 37: a part group
  ThreadPool one(1), two(2);
  for (const Model& candidate :
       {perturbedModel(makePuma560(), 0.3, 2), perturbedModel(makePuma560(), 0.05, 7)}) {
    GcWorkspace scalar(1, 1);
    const double reference = gcError(candidate, problem, scalar, one);
    Eigen::VectorXd width_two;
    std::vector<std::pair<int, int>> runs = {{2, kBuildIsa}, {4, kBuildIsa}, {8, kBuildIsa}};
    for (int isa = kBuildIsa + 1; isa <= gcLaneIsa(); ++isa) runs.emplace_back(4, isa);
    for (const auto& [lanes, isa] : runs) {
      GcWorkspace w1(1, lanes), w2(2, lanes);
      w1.lane_isa = w2.lane_isa = isa;
      const double total = gcError(candidate, problem, w1, one);
      EXPECT_EQ(gcError(candidate, problem, w2, two), total) << lanes << " lanes, isa " << isa;
      EXPECT_EQ(w2.segment_errors, w1.segment_errors) << lanes << " lanes, isa " << isa;
      for (int s = 0; s < problem.numSegments(); ++s)
        EXPECT_NEAR(w1.segment_errors[s], scalar.segment_errors[s],
                    1e-12 * scalar.segment_errors[s])
            << "segment " << s << ", " << lanes << " lanes";
      EXPECT_NEAR(total, reference, 1e-12 * reference) << lanes;
      // Every lane does the same operations whatever the width or instruction set: bit for bit
      // the same (sin and cos included: core/lanes.hpp's kernel).
      if (lanes == 2) width_two = w1.segment_errors;
      EXPECT_EQ(w1.segment_errors, width_two) << lanes << " lanes, isa " << isa;
    }
  }
  EXPECT_THROW(GcWorkspace(1, 3), InputError);
  GcWorkspace too_wide(1, 4);
  too_wide.lane_isa = gcLaneIsa() + 1;
  EXPECT_THROW(gcError(makePuma560(), problem, too_wide, one), InputError);
  EXPECT_EQ(GcWorkspace(1).lanes, defaultGcLanes());
  EXPECT_EQ(GcWorkspace(1).lane_isa, gcLaneIsa());
  EXPECT_TRUE(defaultGcLanes() == kLanes || defaultGcLanes() == 4);
#if DYNID_GC_SIMD
  // A build with the dispatch takes the wider rollouts wherever the CPU has them (else they
  // would be silently unused and every test above would still pass).
  if (__builtin_cpu_supports("avx2")) {
    EXPECT_GE(gcLaneIsa(), kAvx2Isa);
    EXPECT_EQ(defaultGcLanes(), 4);
  }
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")) {
    EXPECT_EQ(gcLaneIsa(), kAvx512Isa);
  }
#endif
}

TEST(GcError, StopsBetweenSegmentsWhenInterruptedOrPastItsDeadline) {
  const Model guess = perturbedModel(makePuma560(), 0.3, 2);
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 10});
  ThreadPool pool(2);
  GcWorkspace workspace(2);
  std::atomic<bool> flag{false};
  RunControl stop;
  stop.stop = &flag;
  const double full = gcError(guess, problem, workspace, pool, stop);
  EXPECT_TRUE(std::isfinite(full));  // a flag that is not set changes nothing
  EXPECT_EQ(full, gcError(guess, problem, workspace, pool));
  flag = true;
  EXPECT_TRUE(std::isnan(gcError(guess, problem, workspace, pool, stop)));
  RunControl late;
  late.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  EXPECT_TRUE(std::isnan(gcError(guess, problem, workspace, pool, late)));
}

TEST(GcError, DivergingRolloutsAreLargeAndFinite) {
  Model bad = makePuma560();
  bad.setLinkInertia(5, RigidInertia<double>());  // a massless last link: singular mass matrix
  const GcProblem problem = makeGcProblem(test::pumaSearchTrajectory(1.0), {.num_segments = 10});
  ThreadPool pool(2);
  GcWorkspace workspace(2);
  const double error = gcError(bad, problem, workspace, pool);
  EXPECT_TRUE(std::isfinite(error));
  EXPECT_EQ(error, 10 * kMaxSegmentError);
}

}  // namespace
}  // namespace dynid
