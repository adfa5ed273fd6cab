#include "core/trajectory.hpp"

#include <gtest/gtest.h>

namespace dynid {
namespace {

/// Sample k's every value encodes k and the row, so a shifted or transposed copy shows.
Trajectory numbered(int joints, int samples) {
  Trajectory t;
  t.resize(joints, samples);
  for (int k = 0; k < samples; ++k) {
    t.time[k] = 0.001 * k;
    for (int j = 0; j < joints; ++j) {
      t.q(j, k) = k + 0.1 * j;
      t.dq(j, k) = 1000 + k + 0.1 * j;
      t.ddq(j, k) = 2000 + k + 0.1 * j;
      t.tau(j, k) = 3000 + k + 0.1 * j;
    }
  }
  return t;
}

TEST(Trajectory, SamplesCopiesTheChunkOfEveryField) {
  const Trajectory t = numbered(3, 10);
  const Trajectory c = t.samples(4, 3);
  ASSERT_EQ(c.numSamples(), 3);
  ASSERT_EQ(c.numJoints(), 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(c.time[k], t.time[4 + k]);
    EXPECT_EQ(c.q.col(k), t.q.col(4 + k));
    EXPECT_EQ(c.dq.col(k), t.dq.col(4 + k));
    EXPECT_EQ(c.ddq.col(k), t.ddq.col(4 + k));
    EXPECT_EQ(c.tau.col(k), t.tau.col(4 + k));
  }
  // The ends and an empty chunk.
  EXPECT_EQ(t.samples(0, 10).q, t.q);
  EXPECT_EQ(t.samples(9, 1).tau(2, 0), t.tau(2, 9));
  EXPECT_EQ(t.samples(10, 0).numSamples(), 0);
}

TEST(Trajectory, TruncateKeepsTheFirstSamples) {
  Trajectory t = numbered(2, 6);
  const Trajectory head = t.samples(0, 4);
  t.truncate(4);
  EXPECT_EQ(t.time, head.time);
  EXPECT_EQ(t.q, head.q);
  EXPECT_EQ(t.dq, head.dq);
  EXPECT_EQ(t.ddq, head.ddq);
  EXPECT_EQ(t.tau, head.tau);
}

}  // namespace
}  // namespace dynid
