// Segment residual blocks evaluated on dynid's thread pool (a ceres::EvaluationCallback), so that
// Ceres itself runs on one thread: its sums (cost, gradient, the Schur complement) then follow the
// residual blocks' order, and a refinement gives the same bits for any thread count. Ceres' own
// threads accumulate per thread and in the order the threads finish.
#pragma once

#include <memory>
#include <vector>

#include <ceres/evaluation_callback.h>
#include <Eigen/Core>

#include "core/parallel.hpp"

namespace ceres {
class CostFunction;
}

namespace dynid {

/// Owns the expensive cost functions (one GC segment each) and evaluates them all, in parallel,
/// when Ceres announces an evaluation (PrepareForEvaluation, with the user's parameter blocks
/// already at the new point). The cost functions given to the ceres::Problem are thin proxies
/// (`add`) that copy the cached residuals and Jacobians; a proxy asked at a point or for Jacobians
/// its cache does not hold evaluates its cost function itself (correct, only serial). Each entry is
/// written by one task, so the results do not depend on the thread count. The callback must
/// outlive the Problem's use of the proxies; set it as the Problem's evaluation_callback.
class ParallelSegmentEvaluation : public ceres::EvaluationCallback {
 public:
  explicit ParallelSegmentEvaluation(ThreadPool& pool);
  ParallelSegmentEvaluation(const ParallelSegmentEvaluation&) = delete;
  ParallelSegmentEvaluation& operator=(const ParallelSegmentEvaluation&) = delete;
  ~ParallelSegmentEvaluation() override;

  /// Takes `cost` (its parameter blocks are `blocks`, the pointers given to AddResidualBlock) and
  /// returns the proxy to add to the problem with the same blocks (the Problem owns it).
  std::unique_ptr<ceres::CostFunction> add(std::unique_ptr<ceres::CostFunction> cost,
                                           std::vector<double*> blocks);

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override;

  /// How many times every entry was evaluated on the pool, and how many proxy calls fell back to
  /// a serial evaluation (tests).
  long batches() const { return batches_; }
  long fallbacks() const;
  /// The longest evaluation with Jacobians so far [s] (what one more Jacobian of every segment
  /// costs, for a time budget).
  double longestJacobians() const { return longest_jacobians_; }

  struct Entry;

 private:
  ThreadPool& pool_;
  std::vector<std::unique_ptr<Entry>> entries_;
  long batches_ = 0;
  double longest_jacobians_ = 0.0;
};

}  // namespace dynid
