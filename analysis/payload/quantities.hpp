// A payload estimate's derived quantities (mass, centre of mass, inertia about it, principal
// moments and axes) with their 95 % intervals by the delta method, which of them the motion
// determines, what it does not see or sees only in combination, and the smallest payload resolved.
#pragma once

#include "analysis/payload/payload.hpp"
#include "identifiability/payload.hpp"

namespace dynid {

/// The two-sided 95 % normal quantile.
inline constexpr double kZ95 = 1.959963984540054;

/// Fills out.quantities, out.unseen, out.combined, out.smallest_mass and out.smallest_moment from
/// the estimate out.standard and its covariance out.covariance (the fit's null directions give
/// what the motion does not see); warns in out.warnings when the principal axes are loose.
void describeBody(PayloadOutcome& out, const PayloadFit& fit);

}  // namespace dynid
