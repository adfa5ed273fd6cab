#include "analysis/floating/gc_data.hpp"

#include <algorithm>
#include <string>

#include "analysis/floating/identifiability.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {
std::string named(const FloatingDataset& dataset) {
  return dataset.file.empty() ? "the dataset" : dataset.file;
}

/// Whether the base's linear velocity is recorded: not where an IMU gave the base motion, nor
/// where it is zero throughout while the base accelerates.
bool recordsLinearVelocity(const FloatingDataset& dataset) {
  if (!dataset.imu_frame.empty()) return false;
  if (dataset.twist.cols() == 0) return true;
  return !(dataset.twist.bottomRows<3>().isZero(0.0) &&
           !dataset.acceleration.bottomRows<3>().isZero(0.0));
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}
}  // namespace

FloatingGcData floatingGcData(const FloatingDataset& dataset,
                              const std::vector<Contact>& contacts) {
  const std::string file = named(dataset);
  if (!dataset.hasTorques())
    throw InputError(file +
                     ": the GC error rolls the motion out with the joint torques, and it "
                     "has none (tau:J columns)");
  FloatingGcData out{dataset.time, dataset.orientation, dataset.twist, dataset.q,
                     dataset.dq,   dataset.tau,         contacts,      {}};
  out.linear_velocity = recordsLinearVelocity(dataset);
  out.flags.resize(contacts.size());
  bool flagged = false;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const Contact& c = contacts[i];
    const FloatingDataset::Wrench* w = dataset.findWrench(c.name);
    if (w != nullptr && w->values.rows() == c.dimension()) {
      out.wrenches.push_back(w->values);
      continue;
    }
    const FloatingDataset::Flag* f = dataset.findFlag(c.name);
    if (f == nullptr)
      throw InputError(file + ": the GC error needs at the contact '" + c.name + "' its " +
                       std::to_string(c.dimension()) + "-component wrench (wrench:" + c.name +
                       ":...) or its flag (contact:" + c.name + ")");
    out.wrenches.emplace_back();
    out.flags[i] = f->holding;
    flagged = true;
  }
  if (!flagged) out.flags.clear();
  return out;
}

FloatingGcData floatingGcData(const FloatingModel& model, const FloatingDataset& dataset,
                              const std::vector<std::string>& contacts) {
  std::vector<std::string> specs = contacts;
  if (specs.empty()) {
    for (const FloatingDataset::Wrench& w : dataset.wrenches)
      specs.push_back(w.frame + (w.values.rows() == 6 ? ":frame" : ""));
    for (const FloatingDataset::Flag& f : dataset.flags)
      if (dataset.findWrench(f.frame) == nullptr) specs.push_back(f.frame);
  }
  return floatingGcData(dataset, contactsOf(model, specs));
}

std::string floatingMotionRefusal(const FloatingDataset& dataset) {
  const Eigen::Index N = dataset.time.size();
  if (dataset.q.rows() == 0 || N < 2) return "";
  std::vector<double> periods;
  for (Eigen::Index k = 0; k + 1 < N; ++k) periods.push_back(dataset.time[k + 1] - dataset.time[k]);
  const double period = median(periods);
  std::vector<double> mismatch, step;
  for (Eigen::Index k = 0; k + 1 < N; ++k) {
    const double h = dataset.time[k + 1] - dataset.time[k];
    if (h > 1.5 * period) continue;  // a gap: no segment crosses it
    const Eigen::VectorXd moved = dataset.q.col(k + 1) - dataset.q.col(k);
    const Eigen::VectorXd integral = 0.5 * h * (dataset.dq.col(k) + dataset.dq.col(k + 1));
    mismatch.push_back((moved - integral).lpNorm<Eigen::Infinity>());
    step.push_back(std::max(moved.lpNorm<Eigen::Infinity>(), integral.lpNorm<Eigen::Infinity>()));
  }
  const double m = median(mismatch), s = median(step);
  if (m <= 0.5 * s || m <= kMotionStepTolerance) return "";
  return named(dataset) +
         "'s samples are not one motion: from one sample to the next the joints step by a "
         "median " +
         formatNumber(s, 3) + " rad, of which " + formatNumber(m, 3) +
         " rad is not the integral of dq over the step (independent states, as a simulation's "
         "random ones: a rollout has nothing to follow)";
}

}  // namespace dynid
