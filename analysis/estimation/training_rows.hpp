// The rows an identification fits (identifiability/rows/fit_rows.hpp) for its training data: the
// torque filter the data went through (the prepare.json beside a dynid prepare output, or the
// caller's), and the stamps and velocities that place its resting samples and reversals.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "analysis/records/prepare_record.hpp"
#include "core/model.hpp"
#include "core/trajectory.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

/// What the caller says of the training torque's filter: nothing (std::nullopt: the prepare.json
/// beside the data file decides), none (order 0) or this filter (order and cutoff; its rate is
/// the data's).
using TorqueFilterChoice = std::optional<TorqueFilter>;

/// The filter a dataset's torque went through, as a prepare.json records it (its filter's order
/// and the torque's own cutoff, tau_cutoff_hz, else cutoff_hz); inactive (order 0) when the record
/// has no filter on the torque. `why` says where it came from, or why there is none.
TorqueFilter torqueFilterOfPreparation(const PreparationFound& found, std::string& why);

/// The stamps and velocities of every sample of a dataset file (8 (joints + 1) bytes per sample,
/// requireMemory), read in chunks.
Trajectory velocitiesOf(const std::string& file, int joints);

/// The median step of `time` as a rate [Hz] (0 for fewer than 2 samples).
double medianRate(const Eigen::VectorXd& time);

/// The rows of `model`'s fit on the training samples whose stamps and velocities `velocities`
/// holds: through `filter` (its rate set from the stamps) when it is active and the model has a
/// drive term that needs sign(dq), otherwise by each sample's own velocity. Throws InputError
/// when the filter's cutoff is not below half the data's rate.
FitRows trainingRows(const Model& model, const Trajectory& velocities, TorqueFilter filter);

}  // namespace dynid
