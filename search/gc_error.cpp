#include "search/gc_error.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "search/gc_lanes.hpp"
#include "search/gc_rollout.hpp"

namespace dynid {

GcWorkspace::PerThread::PerThread(const Model& model)
    : model(model), data(model), q(model.numJoints()), dq(model.numJoints()), tau(0) {}

GcWorkspace::GcWorkspace(int num_threads, int lanes)
    : lanes(lanes == 0 ? defaultGcLanes() : lanes), lane_isa(gcLaneIsa()) {
  if (this->lanes != 1 && this->lanes != 2 && this->lanes != 4 && this->lanes != 8)
    throw InputError("GC lanes must be 1, 2, 4 or 8 (0: " + std::to_string(defaultGcLanes()) +
                     "), not " + std::to_string(lanes));
  threads.resize(static_cast<std::size_t>(num_threads));
}

double gc_detail::segmentError(const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                               const GcProblem& problem, int end) {
  const double error =
      (q - problem.data.q.col(end)).cwiseProduct(problem.weight_q).squaredNorm() +
      (dq - problem.data.dq.col(end)).cwiseProduct(problem.weight_dq).squaredNorm();
  return std::isfinite(error) ? std::min(error, kMaxSegmentError) : kMaxSegmentError;
}

double gcError(const Model& candidate, const GcProblem& problem, GcWorkspace& workspace,
               ThreadPool& pool, const RunControl& control) {
  const int n = candidate.numJoints();
  if (problem.data.numJoints() != n)
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(n));
  if (workspace.lane_isa < kBuildIsa || workspace.lane_isa > gcLaneIsa())
    throw InputError("GC lane instruction set " + std::to_string(workspace.lane_isa) +
                     " is not one this build and CPU offer (at most " +
                     std::to_string(gcLaneIsa()) + ")");
  workspace.segment_errors.resize(problem.numSegments());
  const long evaluation = ++workspace.evaluations;
  std::atomic<bool> stopped{false};
  const int width = workspace.lanes;
  const int groups = (problem.numSegments() + width - 1) / width;
  pool.parallelFor(groups, [&](int g, int thread) {
    if (stopped.load(std::memory_order_relaxed) || control.stopped()) {
      stopped.store(true, std::memory_order_relaxed);
      return;
    }
    // Made on this thread the first time it runs: what a thread writes comes from its own
    // allocator arena, so no cache line is shared with another thread's workspace.
    std::unique_ptr<GcWorkspace::PerThread>& slot = workspace.threads[thread];
    if (!slot) slot = std::make_unique<GcWorkspace::PerThread>(candidate);
    GcWorkspace::PerThread& own = *slot;
    if (width > 1) {
      // Segments g W .. g W + W - 1 in lanes (gc_lanes.cpp), each lane from its own copy.
      gc_detail::rollOutGroup(width, workspace.lane_isa, candidate, evaluation, problem, g * width,
                              own.lane_buffers, workspace.segment_errors);
      return;
    }
    // The pool's other threads read the candidate from a copy in their own memory, refreshed once
    // per evaluation: read in place, its small arrays share cache lines with what the calling
    // thread (thread 0) writes in its arena, and every such write made the other thread's reads
    // miss (two threads 1.78x one, two processes 1.98x). The calling thread reads it in place.
    if (thread != 0 && own.evaluation != evaluation)
      own.model = candidate, own.evaluation = evaluation;
    const Model& model = thread == 0 ? candidate : own.model;
    // Roll out from the recorded start with the recorded (held) torques.
    const int start = problem.starts[g];
    own.q = problem.data.q.col(start);
    own.dq = problem.data.dq.col(start);
    rollOutSegment(model, own.data, problem, g, own.q, own.dq, own.tau);
    workspace.segment_errors[g] =
        gc_detail::segmentError(own.q, own.dq, problem, start + problem.samples_per_segment);
  });
  if (stopped.load()) return std::numeric_limits<double>::quiet_NaN();
  double total = 0.0;
  for (int s = 0; s < problem.numSegments(); ++s) total += workspace.segment_errors[s];
  return total;
}

}  // namespace dynid
