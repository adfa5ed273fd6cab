// The combined estimator on a floating base (`dynid identify --floating-base --method combined`,
// docs/FLOATING.md, "The combined estimator on a floating base"): each set's physically
// consistent estimate refined to fit the set's rows and predict the data's motion together, as
// the fixed-base combined estimator does (search/refinement/combined.hpp): the set's pc objective
// in chi-square units plus the GC error of the data's segments rolled out by the floating forward
// dynamics, each normalised at the start, the GC term held at its noise floor.
#pragma once

#include "analysis/floating/identify.hpp"

namespace dynid {

/// The data as the combined estimator's rollouts (floatingRollable), or InputError naming
/// `method` and why they cannot be rolled out.
FloatingGcData checkCombinedData(const FloatingDataset& data, const std::vector<Contact>& contacts,
                                 FloatingMotion motion);

/// Refines every estimated set of `outcome` (each has pc's estimate: FloatingSetEstimate::physical)
/// by refineCombinedTerms with request.combined's weight and budget: the torque term the set's
/// pc problem (its whitened rows and the divergence from the model's parameters), the GC term
/// floatingGcTerm on `data` with request.gc's segments and the Jacobian along the combinations
/// every floating motion's dynamics see (the carried motion's torques_wrenches base parameters,
/// from request.structural: the rollouts move the limbs and the base, whichever rows the set
/// reads), its floor the GC summary's at the channels' estimated variances for the pc estimate
/// nearest the robot (torques_wrenches', which reads every channel; else the first set's): a
/// start far off has a floor below zero, no floor for the estimate it moves to.
/// Each set's physical, fit.beta and measures (measureSetEstimate) are then the combined
/// estimate's, its covariance pc's (the constraints and the GC term taken as adding no
/// information: a conservative interval), and FloatingSetEstimate::combined says how it went.
/// Throws InputError naming `method` when the data cannot be rolled out (floatingRollable's
/// reasons, the horizon). Without every channel's variance estimated (torques_contacts alone
/// gives no force's) the GC term has no floor, said in outcome.warnings; a set whose start
/// predicts no usable motion keeps pc's estimate and says so there too.
void combineFloatingSets(const FloatingModel& model, const FloatingIdentifyRequest& request,
                         const FloatingDataset& data, const FloatingDataset* validation,
                         FloatingIdentifyOutcome& outcome);

}  // namespace dynid
