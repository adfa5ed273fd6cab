// Trajectories joined for the tests that compare several logs with their concatenation.
#pragma once

#include <vector>

#include "core/trajectory.hpp"

namespace dynid::test {

/// The parts one after another. With `gap` >= 0, each part's stamps follow the previous part's
/// last one after `gap` seconds (a gap, not a sample step: a filter's runs split there, as between
/// logs); otherwise the stamps are kept as they are.
inline Trajectory concatenated(const std::vector<Trajectory>& parts, double gap = -1.0) {
  int total = 0;
  for (const Trajectory& p : parts) total += p.numSamples();
  Trajectory out;
  out.resize(parts.front().numJoints(), total);
  int at = 0;
  double offset = 0.0;
  for (const Trajectory& p : parts) {
    const int m = p.numSamples();
    out.time.segment(at, m) = p.time.array() + offset;
    out.q.middleCols(at, m) = p.q;
    out.dq.middleCols(at, m) = p.dq;
    out.ddq.middleCols(at, m) = p.ddq;
    out.tau.middleCols(at, m) = p.tau;
    if (gap >= 0.0) offset += p.time[m - 1] + gap;
    at += m;
  }
  return out;
}

}  // namespace dynid::test
