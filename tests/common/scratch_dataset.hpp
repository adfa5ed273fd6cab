// Checks shared by the tests of prepare's scratch files.
#pragma once

#include <gtest/gtest.h>

#include "analysis/logs/prepare.hpp"

namespace dynid::test {

/// `scratch` holds the samples of `memory` bit for bit (gtest expectations); `at_least`: the
/// fewest samples that make the comparison mean something.
inline void expectSameSamples(const Trajectory& memory, const ScratchDataset* scratch,
                              int at_least) {
  ASSERT_NE(scratch, nullptr);
  ASSERT_GT(memory.numSamples(), at_least);
  ASSERT_EQ(scratch->numSamples(), memory.numSamples());
  Trajectory chunk;
  scratch->rows(0, memory.numSamples(), chunk);
  EXPECT_EQ(chunk.time, memory.time);
  for (auto member : {&Trajectory::q, &Trajectory::dq, &Trajectory::ddq, &Trajectory::tau})
    EXPECT_EQ(chunk.*member, memory.*member);
}

}  // namespace dynid::test
