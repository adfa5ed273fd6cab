// The GC error on a floating base (docs/FLOATING.md, "The GC error on a floating base"): short
// segments of a floating robot's recorded motion rolled out from their recorded start (the base's
// orientation and twist, q, dq) by the floating forward dynamics, driven by the recorded joint
// torques and the wrenches measured at the contacts, and compared with the recorded state at the
// segment's end. A contact whose wrench is measured pushes with it; one known by its flag alone
// holds where the flag says by the forces that keep it still in the world (a constrained forward
// dynamics), whatever they are.
#pragma once

#include <vector>

#include "core/floating/contact_jacobian.hpp"
#include "core/parallel.hpp"
#include "search/gc_problem.hpp"

namespace dynid {

/// A floating robot's recorded motion, sample by sample (N samples, n joints): the base's
/// orientation (w, x, y, z; base to world) and twist (omega, v; base frame), q, dq, the joint
/// torques (the drives' output) and, for each contact, what it measured in its own frame's axes:
/// a frame contact's wrench (n, f) about its origin (6 x N), a point contact's force (3 x N); or,
/// for a contact whose wrench is not measured, its flag.
struct FloatingGcData {
  Eigen::VectorXd time;
  Eigen::Matrix4Xd orientation;
  Eigen::Matrix<double, 6, Eigen::Dynamic> twist;
  Eigen::MatrixXd q, dq, tau;
  std::vector<Contact> contacts;
  std::vector<Eigen::MatrixXd> wrenches;  // one per contact, in its order (0 x 0: flagged)
  /// Empty, or one per contact: empty where its wrench is measured, else N flags (1: it holds).
  /// A holding contact stays still in the world: its velocity's rate is held at zero,
  ///   J dnu = -dJ nu - omega x (J nu)   (each three rows; J in base-frame axes, nu = (twist, dq)),
  /// by forces J^T lambda with lambda from (J M^-1 J^T) lambda = that - J dnu_free (the least-norm
  /// one where the rows are redundant); a contact moving at a segment's start keeps that velocity
  /// (the recorded state is not projected).
  std::vector<std::vector<char>> flags;
  /// Whether `twist` records the base's linear velocity. False: it does not (a dataset whose base
  /// motion came from an IMU holds zero there); the rollout starts from what it holds (the
  /// joints, the base's rotation and angular velocity do not depend on the base's linear
  /// velocity: the same motion seen from a frame in uniform translation) and the error leaves
  /// the linear velocity out.
  bool linear_velocity = true;
};

/// The segments: `horizon` [s], taken to the nearest whole number of sample periods (the median
/// step; a recording's is rarely round), evenly spaced starts, at most `num_segments` (0: every
/// non-overlapping one), none across a gap (a step over 1.5 periods); `substeps` RK4 steps per
/// sample period, the inputs held over each period.
struct FloatingGcOptions {
  double horizon = 0.05;
  int num_segments = 100;
  int substeps = 1;
  /// Throws InputError naming `horizon` (not positive and finite), `num_segments` (negative) or
  /// `substeps` (below 1).
  void check() const;
};

struct FloatingGcResult {
  /// Each segment's squared error at its end: the joints' (q, dq) and the base twist's entries
  /// (its angular velocity's only without FloatingGcData::linear_velocity) squared, plus the base's
  /// rotation angle between prediction and record squared (rad^2), summed unweighted (as the
  /// paper's unnormalised GC error). A diverging segment counts as kMaxSegmentError.
  Eigen::VectorXd segment_errors;
  std::vector<int> starts;  // each segment's first sample
  int samples_per_segment = 0;
  double horizon = 0.0;  // samples_per_segment sample periods [s]
  /// Their sum: the GC error.
  double error = 0.0;
};

/// The GC error of `candidate` (its parameters) on `data`. Throws InputError (naming the field:
/// `time`, `orientation`, `twist`, `q`, `dq`, `tau`, `wrenches`, `horizon`, `num_segments`,
/// `substeps`, `flags`) when the sizes disagree with the model or each other, a contact's body is
/// not the model's, a contact has neither its wrench nor its flags, the horizon is shorter than
/// half a sample period, a segment would take more than kMaxSegmentSteps RK4 steps (substeps x its
/// periods) or no run holds one segment.
FloatingGcResult floatingGcError(const FloatingModel& candidate, const FloatingGcData& data,
                                 const FloatingGcOptions& options);

/// The segments floatingGcError rolls out (FloatingGcResult's starts, samples_per_segment and
/// horizon; no errors), after checking the data and options as it does (its throws).
FloatingGcResult floatingGcSegments(const FloatingModel& model, const FloatingGcData& data,
                                    const FloatingGcOptions& options);

/// Each segment's end-state difference, one column a segment of `segments`
/// (floatingGcSegments'): q and dq (predicted minus recorded), the base's angular velocity, its
/// linear velocity (zero without FloatingGcData::linear_velocity) and the rotation from the
/// prediction to the record as a rotation vector (angle times axis, the shorter way round); 2 n
/// + 9 rows, NaN where the rollout diverges. floatingSegmentError of a column is the segment's
/// error. `pool` (optional) rolls the segments out in parallel: the same columns for any thread
/// count. Expects data checked by floatingGcSegments.
Eigen::MatrixXd floatingGcResiduals(const FloatingModel& candidate, const FloatingGcData& data,
                                    const FloatingGcResult& segments, int substeps,
                                    ThreadPool* pool = nullptr);

/// A segment's error from its residual column: the squared norm, kMaxSegmentError where that is
/// not finite or above it.
double floatingSegmentError(const Eigen::VectorXd& residual);

}  // namespace dynid
