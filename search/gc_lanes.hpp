// gcError's pieces (gc_error.cpp) and its lane groups (gc_lanes.cpp, the one file that compiles
// the dynamics for Lanes<W>; its rollouts for AVX2 and AVX-512 in gc_lanes_simd.hpp). Internal to
// the search module.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "core/model.hpp"
#include "search/gc_error.hpp"
#include "search/gc_lanes_simd.hpp"

namespace dynid::gc_detail {

/// The squared, weighted error of a predicted end state (q, dq) against the recorded state at
/// sample `end`, kMaxSegmentError when it is not finite or larger.
double segmentError(const Eigen::VectorXd& q, const Eigen::VectorXd& dq, const GcProblem& problem,
                    int end);

/// Rolls segments first .. first + width - 1 (those that exist) of `problem` for `candidate` in
/// `width` lanes (2, 4 or 8; 4 in instruction set `isa`, at most gcLaneIsa()) and writes their
/// segmentError into errors[first ..]. `buffers` is the calling thread's: made (or remade for
/// another width) here, and its lane copy of the candidate refreshed when `evaluation` differs from
/// the one it was made for.
void rollOutGroup(int width, int isa, const Model& candidate, long evaluation,
                  const GcProblem& problem, int first,
                  std::unique_ptr<GcWorkspace::LaneBuffers>& buffers, Eigen::VectorXd& errors);

}  // namespace dynid::gc_detail
