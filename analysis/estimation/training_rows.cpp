#include "analysis/estimation/training_rows.hpp"

#include <algorithm>
#include <vector>

#include "analysis/estimation/streaming.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/memory.hpp"
#include "data/dataset_csv.hpp"

namespace dynid {

TorqueFilter torqueFilterOfPreparation(const PreparationFound& found, std::string& why) {
  TorqueFilter out;
  if (!found.present) {
    why = "no prepare.json beside the data: its torque is taken as unfiltered";
    return out;
  }
  if (!found.record) {
    why =
        "prepare.json beside the data is not one this version reads: its torque is taken as "
        "unfiltered";
    return out;
  }
  const PrepareRecord& r = *found.record;
  const double cutoff = r.tau_cutoff_hz.value_or(r.cutoff_hz);
  if (!(cutoff > 0.0) || r.filter_order < 1) {
    why = "prepare.json: the torque was not filtered";
    return out;
  }
  out.order = r.filter_order;
  out.cutoff = cutoff;
  why = "prepare.json: the torque's low-pass";
  return out;
}

Trajectory velocitiesOf(const std::string& file, int joints) {
  DatasetReader reader(file, joints);
  std::vector<double> time, dq;  // dq joint-major per sample
  Trajectory chunk;
  while (const int got = reader.read(chunk, kStreamChunkSamples)) {
    requireMemory(static_cast<double>(time.size() + static_cast<std::size_t>(got)) * (joints + 1) *
                      sizeof(double),
                  file + ": the stamps and velocities of its samples");
    time.insert(time.end(), chunk.time.data(), chunk.time.data() + got);
    dq.insert(dq.end(), chunk.dq.data(), chunk.dq.data() + static_cast<std::size_t>(got) * joints);
  }
  const auto count = static_cast<Eigen::Index>(time.size());
  Trajectory out;
  out.time = Eigen::Map<const Eigen::VectorXd>(time.data(), count);
  out.dq = Eigen::Map<const Eigen::MatrixXd>(dq.data(), joints, count);
  out.q.resize(joints, 0);
  out.ddq.resize(joints, 0);
  out.tau.resize(joints, 0);
  return out;
}

double medianRate(const Eigen::VectorXd& time) {
  if (time.size() < 2) return 0.0;
  std::vector<double> steps(static_cast<std::size_t>(time.size() - 1));
  for (Eigen::Index k = 1; k < time.size(); ++k)
    steps[static_cast<std::size_t>(k - 1)] = time[k] - time[k - 1];
  const auto middle = steps.begin() + static_cast<long>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  return *middle > 0.0 ? 1.0 / *middle : 0.0;
}

FitRows trainingRows(const Model& model, const Trajectory& velocities, TorqueFilter filter) {
  if (!filter.active()) return FitRows(model);
  filter.rate = medianRate(velocities.time);
  if (!(filter.cutoff < 0.5 * filter.rate))
    throw InputError("the torque's filter at " + formatNumber(filter.cutoff, 4) +
                     " Hz is not below half the data's rate (" + formatNumber(filter.rate, 6) +
                     " Hz): give `torque_filter` none, or the filter the torque went through");
  return FitRows(model, velocities.time, velocities.dq, filter);
}

}  // namespace dynid
