// The GC term of the combined estimator on a floating base (docs/FLOATING.md, "The combined
// estimator on a floating base"): a floating robot's recorded motion rolled out
// (floating_gc.hpp) as the GC term of refineCombinedTerms (search/refinement/combined.hpp), over
// the floating standard vector (the base body's 10 parameters, then the limbs').
#pragma once

#include "search/floating/floating_gc.hpp"
#include "search/refinement/combined.hpp"

namespace dynid {

/// The GC term on `data`'s segments (floatingGcSegments with `options`): error(theta) is
/// floatingGcError's for the model with parameters theta; linearise gives the segments' residual
/// columns (floatingGcResiduals, stacked) and their Jacobian in theta, J_beta P, with P
/// `projection` (b x p: the combinations the rollouts depend on, e.g. the carried motion's
/// torques_wrenches base parameters, which every floating motion's dynamics see) and J_beta by
/// forward differences along the pseudo-inverse's columns (beta_i moved by 1e-6 of the larger
/// of |beta_i| and 1e-6 max |beta|: truncation about 1e-6 relative, round-off below it), the b + 1
/// rollouts spread over `num_threads` (0: every core; the same result for any count). No floor (the
/// caller gives one: CombinedOptions::given_floor). `structure` and `data` must outlive the term.
/// Throws InputError as floatingGcSegments, or when `projection` has not p columns.
GcTerm floatingGcTerm(const FloatingModel& structure, const FloatingGcData& data,
                      const FloatingGcOptions& options, const Eigen::MatrixXd& projection,
                      int num_threads = 1);

}  // namespace dynid
