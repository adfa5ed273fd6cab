#include "search/gc_problem.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(GcProblem, RefusesSegmentsOfMoreThanAMillionSteps) {
  // 0.05 s in steps of 1e-6 s is 5e4 steps: accepted; 2 s in steps of 1e-6 s is 2e6: refused.
  const Trajectory data = test::pumaSearchTrajectory(6.0);
  EXPECT_NO_THROW(makeGcProblem(data, {.num_segments = 1, .step = 1e-6}));
  try {
    makeGcProblem(data, {.horizon = 2.0, .num_segments = 1, .step = 1e-6});
    ADD_FAILURE() << "a 2e6-step segment was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2e+06 integration steps"), std::string::npos) << e.what();
  }
}

TEST(GcProblem, NormalisationAndSegmentChoices) {
  const Trajectory data = test::pumaSearchTrajectory();
  const GcProblem plain = makeGcProblem(data, {});
  const GcProblem normalised = makeGcProblem(data, {.normalise = true});
  EXPECT_EQ(plain.weight_q, Eigen::VectorXd::Ones(6));
  EXPECT_NEAR(normalised.weight_q[0],
              1.0 / std::sqrt((data.q.row(0).array() - data.q.row(0).mean()).square().mean()),
              1e-9);
  const GcProblem random_a = makeGcProblem(data, {.random_starts = true, .seed = 3});
  const GcProblem random_b = makeGcProblem(data, {.random_starts = true, .seed = 3});
  EXPECT_EQ(random_a.starts, random_b.starts);
  EXPECT_EQ(makeGcProblem(data, {.num_segments = 0}).numSegments(), 120);
}

TEST(GcProblem, SegmentsNeverCrossARunBoundary) {
  // Two runs, as `dynid prepare` writes a log split at a gap: the second starts 2 s after the
  // first ends. 0.05 s horizons at 1 kHz: 50 samples per segment.
  const Trajectory data = test::pumaSearchTrajectory(0.5);
  Trajectory runs = data;
  const int n = data.numSamples(), half = n / 2;
  for (int k = half; k < n; ++k) runs.time[k] += 2.0;
  for (bool random : {false, true}) {
    SegmentOptions options;
    options.num_segments = 0;
    options.random_starts = random;
    if (random) options.num_segments = 200;
    const GcProblem p = makeGcProblem(runs, options);
    ASSERT_GT(p.numSegments(), 0);
    for (int start : p.starts) {
      const int end = start + p.samples_per_segment;
      ASSERT_LT(end, n);
      // Inside one run: no step of the segment is the 2 s jump.
      EXPECT_NEAR(runs.time[end] - runs.time[start], 0.05, 1e-9) << start;
    }
    if (!random) {
      // Every non-overlapping slot of each run: (half - 1) / 50 + (n - half - 1) / 50.
      EXPECT_EQ(p.numSegments(), (half - 1) / 50 + (n - half - 1) / 50);
      EXPECT_TRUE(std::find(p.starts.begin(), p.starts.end(), half) != p.starts.end());
    }
  }
}

TEST(GcProblem, RejectsBadSettings) {
  const Trajectory data = test::pumaSearchTrajectory(0.5);
  EXPECT_THROW(makeGcProblem(data, {.horizon = 0.0125}), InputError);    // not whole samples
  EXPECT_THROW(makeGcProblem(data, {.num_segments = 100}), InputError);  // room for 10
  EXPECT_THROW(makeGcProblem(data, {.step = 3e-4}), InputError);
  Trajectory uneven = data;
  uneven.time[3] += 3e-4;
  EXPECT_THROW(makeGcProblem(uneven, {}), InputError);
}

}  // namespace
}  // namespace dynid
