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
#include "core/run_control.hpp"
#include "core/trajectory.hpp"
#include "search/gc_problem.hpp"

namespace dynid {

/// The lanes a GcWorkspace takes by default: kLanes (core/lanes.hpp: one register of the CPU the
/// build targets), except that a build for any x86-64 running on a CPU with AVX2 or AVX-512 takes
/// 4, rolled in AVX registers by a rollout compiled for that set and chosen at run time
/// (search/gc_lanes_simd.hpp).
int defaultGcLanes();

/// The widest instruction set this build and the CPU it runs on offer the GC's 4 lanes
/// (core/lanes.hpp's kAvx512Isa, kAvx2Isa, or kBuildIsa), checked once: core/sin_cos.hpp's
/// cpuLaneIsa().
int gcLaneIsa();

/// Per-thread workspace for GC-error evaluations of one model structure. Each thread's buffers are
/// made by gcError on that thread, the first time it runs there: glibc gives each thread its own
/// allocator arena, so what one thread writes never shares a cache line with another's. The pool's
/// threads other than the caller's also read the candidate from their own copy (gc_error.cpp).
///
/// `lanes` is how many segments one thread rolls out at once (core/lanes.hpp): 1 is the scalar
/// path, one segment at a time (the reference); 2, 4 or 8 roll that many in SIMD lanes; 0 (the
/// default) takes defaultGcLanes(). A segment's error does not depend on the lane count beyond
/// round-off in Eigen's sums (see gcError), and not at all on the thread count.
/// `lane_isa` is the instruction set 4 lanes roll in (core/lanes.hpp's kBuildIsa, kAvx2Isa or
/// kAvx512Isa): by default the widest this build and CPU offer (gcLaneIsa()); a narrower one may
/// be set (benchmarks and tests compare them), a wider one is an InputError from gcError.
struct GcWorkspace {
  explicit GcWorkspace(int num_threads, int lanes = 0);
  /// One thread's lane buffers (gc_lanes.cpp: a model, a Data and the state in Lanes<W>).
  struct LaneBuffers {
    virtual ~LaneBuffers() = default;
  };
  struct PerThread {
    explicit PerThread(const Model& model);
    Model model;           // a copy of the candidate (threads other than the caller's)
    long evaluation = -1;  // the evaluation `model` was copied for
    Data data;
    Eigen::VectorXd q, dq, tau;                 // tau: rollOutSegment's scratch (unused for double)
    std::unique_ptr<LaneBuffers> lane_buffers;  // made on the first lane group
  };
  std::vector<std::unique_ptr<PerThread>> threads;  // null until that thread's first segment
  Eigen::VectorXd segment_errors;
  long evaluations = 0;
  int lanes = 1;  // 1, 2, 4 or 8
  int lane_isa = 0;
};

/// Squared prediction error of each segment into workspace.segment_errors, summed in segment order
/// (the same result for any thread count). With lanes (workspace.lanes > 1), each segment's error
/// equals the scalar path's to within 1e-12 relative (tests/search/gc_error_test.cpp) where the
/// error is well above round-off (at the truth of noise-free data both are round-off, below
/// 1e-24): a lane does every operation a double does, but Eigen sums a double dot product in SIMD
/// packets and a lane's in order, and a lane's sin and cos (core/lanes.hpp's kernel) may round the
/// other way from the C library's (both within 1 ulp), so the two differ by an ulp or so per sum
/// or rotation, grown over the horizon's steps. The lane count and instruction set change nothing
/// (every lane's operations are the same for any width).
/// Before each segment (each group of `lanes` segments) it polls `control` (stopped(): the flag and
/// the deadline): once stopped, the remaining segments are skipped and the result is NaN (the
/// evaluation did not finish). Throws InputError when the model's joint count differs from the
/// data's, or workspace.lanes is not 1, 2, 4 or 8.
double gcError(const Model& candidate, const GcProblem& problem, GcWorkspace& workspace,
               ThreadPool& pool, const RunControl& control = {});

}  // namespace dynid
