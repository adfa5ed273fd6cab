// The paper's generalized-coordinate (GC) error: how well a candidate model predicts the recorded
// state a short horizon ahead.
//
// A segment starts at a recorded sample (q, dq), applies the recorded torques (each held until the
// next sample, as recorded) for `horizon` seconds with the given integrator and step, and compares
// the predicted state with the recorded one at the end. The GC error is the paper's eq. (2):
//     GC = sum over segments i of |s_i - s_hat_i|^2,   s = (q, dq),
// optionally with q_j and dq_j divided by their standard deviation over the dataset so that
// neither dominates.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/integrators.hpp"
#include "core/parallel.hpp"
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

/// The most integration steps one segment may take (horizon / step): about 1.5 s of RK4 on a
/// 6-joint arm, so a GC evaluation polls its stop condition (GcStop) at least that often.
inline constexpr double kMaxSegmentSteps = 1e6;

/// A segment whose prediction diverges (non-finite, or a squared error above this) counts as this,
/// so optimisers always see a finite error.
inline constexpr double kMaxSegmentError = 1e6;

/// Per-thread workspace for GC-error evaluations of one model structure. Each thread's buffers are
/// made by gcError on that thread, the first time it runs there: glibc gives each thread its own
/// allocator arena, so what one thread writes never shares a cache line with another's. The pool's
/// threads other than the caller's also read the candidate from their own copy (gc_error.cpp).
struct GcWorkspace {
  explicit GcWorkspace(int num_threads);
  struct PerThread {
    explicit PerThread(const Model& model);
    Model model;           // a copy of the candidate (threads other than the caller's)
    long evaluation = -1;  // the evaluation `model` was copied for
    Data data;
    Eigen::VectorXd q, dq, tau;  // tau: rollOutSegment's scratch (unused for double)
  };
  std::vector<std::unique_ptr<PerThread>> threads;  // null until that thread's first segment
  Eigen::VectorXd segment_errors;
  long evaluations = 0;
};

/// When an evaluation must stop early: an interrupt flag (Ctrl-C) and a deadline (a time budget).
struct GcStop {
  const std::atomic<bool>* flag = nullptr;
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  bool requested() const;
};

/// Squared prediction error of each segment into workspace.segment_errors, summed in segment order
/// (the same result for any thread count). Before each segment it polls `stop`: once requested,
/// the remaining segments are skipped and the result is NaN (the evaluation did not finish).
/// Throws InputError when the model's joint count differs from the data's.
double gcError(const Model& candidate, const GcProblem& problem, GcWorkspace& workspace,
               ThreadPool& pool, const GcStop& stop = {});

}  // namespace dynid
