// The GC error of a floating identification's estimates (docs/FLOATING.md, "The GC error on a
// floating base"): the paper's measure beside the residuals, per sensor set.
#pragma once

#include "analysis/floating/identify.hpp"

namespace dynid {

/// The estimate of a set as a model: pc's standard parameters; for ols and wls the set's base
/// parameters completed by the model's own along what the set does not determine
/// (BaseParameters::standardFromBase with the model as prior: the estimate's base parameters
/// exactly, the rest the model's).
FloatingModel floatingEstimateModel(const FloatingModel& model, const FloatingSetEstimate& set);

/// Fills outcome.gc and every estimated set's gc_train and gc_test as request.gc asks: each
/// estimate (floatingEstimateModel) and the model's own parameters rolled out over `data`'s motion
/// and `validation`'s (floatingGcError with outcome.contacts, each pushing with its measured wrench
/// or, known by its flag alone, held still while it holds), and the floor the inputs' noise gives
/// (FloatingGcSummary). Data it cannot roll out are said in outcome.gc.refused
/// (validation_refused), not thrown: no request (`gc` unset), no joint torques, a contact with
/// neither wrench nor flag, a carried base's support known by its flag alone, samples that are not
/// one motion (floatingMotionRefusal), a horizon the data do not hold.
void measureFloatingGc(const FloatingModel& model, const FloatingIdentifyRequest& request,
                       const FloatingDataset& data, const FloatingDataset* validation,
                       FloatingIdentifyOutcome& outcome);

}  // namespace dynid
