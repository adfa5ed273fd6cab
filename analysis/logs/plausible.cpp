#include "analysis/logs/prepare_steps.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid::prepare_steps {

namespace {

/// The per-joint bounds of `given` (empty: `fallback` for all; one value: for all).
Eigen::VectorXd boundsOf(const Eigen::VectorXd& given, double fallback, int n, const char* what) {
  if (given.size() == 0) return Eigen::VectorXd::Constant(n, fallback);
  if (given.size() == 1) return Eigen::VectorXd::Constant(n, given[0]);
  if (given.size() != n)
    throw InputError(std::string(what) + " has " + std::to_string(given.size()) +
                     " values; the log has " + std::to_string(n) +
                     " joints: give one or one per "
                     "joint");
  return given;
}

/// Every sample of one signal of joint j (the time: j ignored), the train set's then the validate
/// set's.
Eigen::VectorXd allSamples(const PrepareOutcome& out, ScratchDataset::Signal signal, int j) {
  const Eigen::Index train = out.trainSamples(), validate = out.validateSamples();
  Eigen::VectorXd all(train + validate);
  if (out.scratch_train) {
    if (train > 0) all.head(train) = out.scratch_train->column(signal, j);
    if (validate > 0) all.tail(validate) = out.scratch_validate->column(signal, j);
    return all;
  }
  // Each set's samples when it has any (an empty set's matrices hold no storage to take a row of).
  for (const auto& [t, at, count] :
       {std::tuple{&out.train, Eigen::Index{0}, train}, std::tuple{&out.validate, train, validate}})
    if (count > 0)
      all.segment(at, count) = signal == ScratchDataset::kTime
                                   ? t->time
                                   : Eigen::VectorXd((t->*matrixOf(signal)).row(j).transpose());
  return all;
}

/// Row j of a signal over the train and validate sets: the 99th percentile of its magnitude (spikes
/// aside), its peak and the sample of the peak (train then validate).
struct Magnitude {
  double p99 = 0.0, peak = 0.0;
  Eigen::Index at = 0;
};
Magnitude magnitudeOf(const PrepareOutcome& out, ScratchDataset::Signal signal, int j) {
  Magnitude m;
  Eigen::VectorXd all = allSamples(out, signal, j).cwiseAbs();
  for (Eigen::Index k = 0; k < all.size(); ++k)
    if (all[k] > m.peak) m.peak = all[k], m.at = k;
  const auto at =
      static_cast<std::ptrdiff_t>(std::floor(0.99 * static_cast<double>(all.size() - 1)));
  std::nth_element(all.begin(), all.begin() + at, all.end());
  m.p99 = all[at];
  return m;
}

/// Velocities and accelerations no robot reaches are a unit or column mistake, never data: an
/// InputError naming the joint, the value, the likely causes and the options that fix them. A
/// log whose joints barely move gets a warning (the stamps may be in a smaller unit than given).
/// The angle-unit mismatch as the first sentence of an error ("" when there is none).
std::string unitHint(const PrepareOutcome& out, const PrepareOptions& options) {
  const std::string mismatch = angleUnitMismatch(out.columns, options.angle_scale);
  return mismatch.empty() ? "" : "First: " + mismatch + ". ";
}

}  // namespace

void checkPlausible(const PrepareOptions& options, int n, bool ddq_meaningful,
                    PrepareOutcome& out) {
  const Eigen::VectorXd dq_bound = boundsOf(options.dq_bound, kPlausibleSpeed, n, "`dq_max`");
  const Eigen::VectorXd ddq_bound =
      boundsOf(options.ddq_bound, kPlausibleAcceleration, n, "`ddq_max`");
  double fastest = 0.0;
  for (int j = 0; j < n; ++j)
    for (int order : {1, 2}) {
      if (order == 2 && !ddq_meaningful) continue;
      const Magnitude m =
          magnitudeOf(out, order == 1 ? ScratchDataset::kDq : ScratchDataset::kDdq, j);
      if (order == 1) fastest = std::max(fastest, m.p99);
      const double bound = (order == 1 ? dq_bound : ddq_bound)[j];
      if (!(m.p99 > bound)) continue;
      const bool given = (order == 1 ? options.dq_bound : options.ddq_bound).size() > 0;
      throw InputError(
          "joint " + std::to_string(j + 1) + ": |" + (order == 1 ? "dq" : "ddq") + "| reaches " +
          formatNumber(m.peak, 4) + (order == 1 ? " rad/s" : " rad/s^2") +
          " at t = " + formatNumber(allSamples(out, ScratchDataset::kTime, 0)[m.at], 6) +
          " s and exceeds " + formatNumber(bound, 4) + " for over 1 % of the samples, more than " +
          (given ? std::string("the bound (`dq_max`, `ddq_max`, or 3 times `robot`'s limits)")
                 : std::string("any robot moves")) +
          ": the log's units or columns are likely wrong. " + unitHint(out, options) +
          "Check `time_unit` (stamps in a larger "
          "unit than given make motion look fast), `angle_unit` (degrees read as radians: 57 "
          "times) and the `q_columns` columns (positions, in joint order?); if the motion is real, "
          "raise " +
          (order == 1 ? "`dq_max`" : "`ddq_max`"));
    }
  if (fastest < 1e-3)
    out.warnings.push_back("no joint moves faster than " + formatNumber(fastest, 3) +
                           " rad/s for 1 % of the time: the robot barely moves, or the stamps are "
                           "in a smaller unit than `time_unit` says (milliseconds read as "
                           "seconds make motion look 1000 times slower)");
}

}  // namespace dynid::prepare_steps
