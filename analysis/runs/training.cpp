#include "analysis/runs/training.hpp"

#include <algorithm>

#include "analysis/estimation/streaming.hpp"
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

/// Reads the file's first kRestSamples samples for their stamps and velocities (returned; q, ddq
/// and tau with no samples), what the rest velocities are measured on. When the file ends within
/// kWholeHeadSamples, its samples are kept whole in `head` with the reader (at the end); otherwise
/// `head` keeps nothing and the stream reads the file again.
Trajectory readHead(const std::string& file, int joints, DatasetHead& head) {
  head.reader = std::make_unique<DatasetReader>(file, joints);
  // Room for every sample (a shorter file's never touched), shrunk after.
  Trajectory out;
  out.time.resize(kRestSamples);
  out.dq.resize(joints, kRestSamples);
  int count = 0;
  for (Trajectory chunk; count < kRestSamples;) {
    const int got =
        head.reader->read(chunk, std::min(kStreamChunkSamples, kRestSamples - count), head.pool);
    if (got == 0) break;
    out.time.segment(count, got) = chunk.time;
    out.dq.middleCols(count, got) = chunk.dq;
    count += got;
    if (count <= kWholeHeadSamples) {
      head.chunks.push_back(std::move(chunk));
    } else if (!head.chunks.empty()) {
      head.chunks.clear();
      head.chunks.shrink_to_fit();
    }
  }
  if (count > kWholeHeadSamples) head.reader.reset();
  out.time.conservativeResize(count);
  out.dq.conservativeResize(joints, count);
  out.q.resize(joints, 0);
  out.ddq.resize(joints, 0);
  out.tau.resize(joints, 0);
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
                          const TorqueFilterChoice& choice, DatasetHead* head) {
  TrainingSet out(model);
  if (!data) out.preparation = findPreparation(file);
  out.torque_filter = torqueFilterFor(choice, data, out.preparation, out.torque_filter_source);
  const bool filtered = out.torque_filter.active() && needsSign(model);
  {
    const bool once = head != nullptr && data == nullptr && !filtered;
    const Trajectory velocities = once ? readHead(file, model.numJoints(), *head)
                                       : velocitiesFor(file, data, model.numJoints(), filtered);
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
