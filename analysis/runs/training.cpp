#include "analysis/runs/training.hpp"

#include <algorithm>

#include "analysis/runs/arm.hpp"
#include "core/drive_terms.hpp"
#include "core/errors.hpp"

namespace dynid {

namespace {

/// The training data's stamps and velocities: every sample's when the fit needs them all (a
/// filtered torque and a model with friction that needs sign(dq)), otherwise the first
/// kRestSamples (the rest velocities' measure).
Trajectory velocitiesFor(const std::string& file, const Trajectory* data, int n, bool all) {
  if (data == nullptr) return all ? velocitiesOf(file, n) : restSamplesOf(file, n);
  Trajectory out;
  out.time = data->time;
  out.dq = data->dq;
  out.q.resize(n, 0);
  out.ddq.resize(n, 0);
  out.tau.resize(n, 0);
  return out;
}

/// Each joint's rest velocity: given, or measured on the first kRestSamples of the training data.
std::vector<RestVelocity> restOf(const std::vector<double>& given, const Trajectory& velocities) {
  const Eigen::Index count = std::min<Eigen::Index>(velocities.time.size(), kRestSamples);
  const Eigen::MatrixXd dq = velocities.dq.leftCols(count);
  if (!given.empty()) return givenRestVelocities(given, dq);
  return measureRestVelocities(dq, velocities.time.head(count));
}

/// The torque's filter: the choice's, else the prepare.json beside the data file's.
TorqueFilter torqueFilterFor(const TorqueFilterChoice& choice, const Trajectory* data,
                             const PreparationFound& found, std::string& why) {
  if (choice) {
    why = choice->active() ? "given" : "none: given";
    return *choice;
  }
  if (data != nullptr) {
    why = "data in memory: its torque is taken as unfiltered (give `torque_filter`)";
    return {};
  }
  return torqueFilterOfPreparation(found, why);
}

bool needsSign(const Model& model) {
  for (int k = 0; k < kDriveTermCount; ++k)
    if (model.driveTerms().has(k) && kDriveTermTable[k].signed_by_velocity) return true;
  return false;
}

}  // namespace

TrainingSet trainingSetOf(const Model& model, const std::string& file, const Trajectory* data,
                          const std::vector<double>& rest_velocity,
                          const TorqueFilterChoice& choice) {
  TrainingSet out(model);
  if (!data) out.preparation = findPreparation(file);
  out.torque_filter = torqueFilterFor(choice, data, out.preparation, out.torque_filter_source);
  const bool filtered = out.torque_filter.active() && needsSign(model);
  {
    const Trajectory velocities = velocitiesFor(file, data, model.numJoints(), filtered);
    out.rest = restOf(rest_velocity, velocities);
    out.model.rest_velocities = restThresholds(out.rest);
    try {
      out.rows = trainingRows(out.model, velocities, filtered ? out.torque_filter : TorqueFilter{});
    } catch (const InputError& e) {
      throw InputError(file + ": " + e.what());
    }
  }
  if (filtered) {
    out.torque_filter = out.rows.filter();
    out.filter_reach = out.rows.reach();
  } else if (out.torque_filter.active()) {
    out.torque_filter_source += "; no friction term needs sign(dq): nothing to reproduce";
  }
  return out;
}

}  // namespace dynid
