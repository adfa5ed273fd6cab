// The GC error's problem: a dataset cut into short segments, each rolled out from its recorded
// start state with the recorded torques (gc_error.hpp measures it, gc_rollout.hpp rolls a segment).
#pragma once

#include <cstdint>
#include <vector>

#include "core/integrators.hpp"
#include "core/trajectory.hpp"

namespace dynid {

struct SegmentOptions {
  double horizon = 0.05;       // [s]; the paper's "fixed time interval"
  int num_segments = 100;      // 0: every non-overlapping segment of the dataset
  bool random_starts = false;  // seeded random starts instead of evenly spaced ones
  std::uint64_t seed = 1;
  IntegratorType integrator = IntegratorType::kRk4;
  double step = 0.0;       // integration step [s]; 0: the dataset's sample period
  bool normalise = false;  // divide q_j, dq_j errors by their spread over the dataset
};

/// The prepared problem: the dataset, the segments and the weights.
struct GcProblem {
  Trajectory data;
  std::vector<int> starts;  // sample index of each segment's start
  int samples_per_segment = 0;
  int substeps = 1;  // integration steps per sample period
  double step = 0.0;
  IntegratorType integrator = IntegratorType::kRk4;
  Eigen::VectorXd weight_q, weight_dq;  // per joint (1 without normalisation)

  int numSegments() const { return static_cast<int>(starts.size()); }
};

/// Builds segments from a dataset. The sample period is the median step; a step longer than 1.5
/// periods separates two runs (a `dynid prepare` output split at gaps, or several files), and no
/// segment crosses it. Throws InputError when the horizon is not a whole number of sample periods
/// (to 1e-6), another step differs from the period (to 1e-6 relative), the step does not divide
/// it, a segment would take more than kMaxSegmentSteps integration steps, or no run holds one
/// segment; asks for no more segments than fit without overlap when evenly spaced.
GcProblem makeGcProblem(const Trajectory& data, const SegmentOptions& options);

/// Segment options with normalise on (dynid study's and the combined estimator's default).
inline SegmentOptions normalisedSegments() {
  SegmentOptions out;
  out.normalise = true;
  return out;
}

/// makeGcProblem with at most options.num_segments evenly spaced segments: all the dataset holds
/// when fewer fit (random starts and num_segments 0 as makeGcProblem). Throws as makeGcProblem.
GcProblem makeGcProblemUpTo(const Trajectory& data, SegmentOptions options);

/// The most integration steps one segment may take (horizon / step): about 1.5 s of RK4 on a
/// 6-joint arm, so a GC evaluation polls its stop condition (GcStop) at least that often.
inline constexpr double kMaxSegmentSteps = 1e6;

/// A segment whose prediction diverges (non-finite, or a squared error above this) counts as this,
/// so optimisers always see a finite error.
inline constexpr double kMaxSegmentError = 1e6;

}  // namespace dynid
