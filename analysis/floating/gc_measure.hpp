// The GC error of a floating identification's estimates (docs/FLOATING.md, "The GC error on a
// floating base"): the paper's measure beside the residuals, per sensor set.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "analysis/floating/identify.hpp"

namespace dynid {

/// The estimate of a set as a model: pc's standard parameters; for ols and wls the set's base
/// parameters completed by the model's own along what the set does not determine
/// (BaseParameters::standardFromBase with the model as prior: the estimate's base parameters
/// exactly, the rest the model's).
FloatingModel floatingEstimateModel(const FloatingModel& model, const FloatingSetEstimate& set);

/// The dataset as a rollout's data (floatingGcData with `contacts`), or nothing with `why` set:
/// samples that are not one motion (floatingMotionRefusal), a contact with neither wrench nor
/// flag, a carried base's support known by its flag alone (it holds the base while moving it, and
/// the flag does not say how).
std::optional<FloatingGcData> floatingRollable(const FloatingDataset& dataset,
                                               const std::vector<Contact>& contacts,
                                               FloatingMotion motion, std::string& why);

/// The channels' variances the weighted fits estimated: torques_wrenches' (it reads every channel
/// and weights every set), else the torques' from a set that reads them and the forces' and
/// moments' from one that reads those; nothing with ols, or when a channel the data have is not
/// estimated.
std::optional<ChannelVariances> floatingEstimatedVariances(const FloatingIdentifyOutcome& outcome);

/// FloatingGcSummary's floor on `data` for `model`, whose GC error there is `error`: the mean over
/// kGcFloorDraws draws (from `seed`) of GC(inputs + noise) - GC(inputs), the noise at the
/// variances `v`; NaN for a candidate whose rollout diverged (no floor).
double floatingGcFloor(const FloatingModel& model, const FloatingGcData& data,
                       const FloatingGcOptions& options, const ChannelVariances& v, double error,
                       std::uint64_t seed);

/// Fills outcome.gc and every estimated set's gc_train and gc_test as request.gc asks: each
/// estimate (floatingEstimateModel) and the model's own parameters rolled out over `data`'s motion
/// and `validation`'s (floatingGcError with outcome.contacts, each pushing with its measured wrench
/// or, known by its flag alone, held still while it holds), and the floor the inputs' noise gives
/// (FloatingGcSummary). Data it cannot roll out are said in outcome.gc.refused
/// (validation_refused), not thrown: no request (`gc` unset), no joint torques, a contact with
/// neither wrench nor flag, a carried base's support known by its flag alone, samples that are not
/// one motion (floatingMotionRefusal), a horizon the data do not hold, and a run whose
/// `combined.control` was interrupted (Ctrl-C: its result is wanted now).
void measureFloatingGc(const FloatingModel& model, const FloatingIdentifyRequest& request,
                       const FloatingDataset& data, const FloatingDataset* validation,
                       FloatingIdentifyOutcome& outcome);

}  // namespace dynid
