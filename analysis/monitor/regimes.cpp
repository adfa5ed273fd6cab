#include "analysis/monitor/regimes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "analysis/monitor/states.hpp"

namespace dynid {

namespace {

/// The 95th percentile of |x| over the samples above 1 % of its largest |x|: the motion's typical
/// top value, whatever share of the log holds a pose.
double scaleOf(const Eigen::VectorXd& x) {
  const double largest = x.size() > 0 ? x.cwiseAbs().maxCoeff() : 0.0;
  std::vector<double> values;
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (std::abs(x[k]) > 0.01 * largest) values.push_back(std::abs(x[k]));
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[static_cast<std::size_t>(k)];
}

}  // namespace

void MovingRegimes::reset(const Eigen::VectorXd& speed_scale,
                          const Eigen::VectorXd& acceleration_scale) {
  speed_scale_ = speed_scale;
  acceleration_scale_ = acceleration_scale;
  const Eigen::Index n = speed_scale.size();
  regime_ = Eigen::VectorXi::Constant(n, regimeIndex(1, false));
  velocity_ = acceleration_ = Eigen::VectorXd::Zero(n);
  last_slow_ = last_fast_ = last_accelerating_ = Eigen::VectorXd::Constant(n, -1e300);
  fresh_ = true;
}

const Eigen::VectorXi& MovingRegimes::update(double t, double dt, const Eigen::VectorXd& dq) {
  if (!enabled()) return regime_;
  // After a gap the acceleration is unknown: steady until it is seen again.
  const bool restart = fresh_ || dt <= 0.0;
  fresh_ = false;
  const double share = restart ? 0.0 : dt / (kVelocitySmoothingSeconds + dt);
  for (Eigen::Index j = 0; j < dq.size(); ++j) {
    if (restart) {
      velocity_[j] = dq[j];
      acceleration_[j] = 0.0;
    } else {  // per joint, so that a sample allocates nothing
      const double before = velocity_[j];
      velocity_[j] += share * (dq[j] - before);
      acceleration_[j] += share * ((velocity_[j] - before) / dt - acceleration_[j]);
    }
    const double v = std::abs(velocity_[j]), a = std::abs(acceleration_[j]);
    const double vs = speed_scale_[j], as = acceleration_scale_[j];
    if (vs > 0.0 && v < kSlowSpeedShare * vs) last_slow_[j] = t;
    if (vs > 0.0 && v > kFastSpeedShare * vs) last_fast_[j] = t;
    if (as > 0.0 && a > kAcceleratingShare * as) last_accelerating_[j] = t;
    // Slow takes precedence over fast within the memory: a reversal's error outlasts it.
    const int speed = t - last_slow_[j] <= kRegimeMemorySeconds   ? 0
                      : t - last_fast_[j] <= kRegimeMemorySeconds ? 2
                                                                  : 1;
    regime_[j] = regimeIndex(speed, t - last_accelerating_[j] <= kRegimeMemorySeconds);
  }
  return regime_;
}

RegimeScales measureRegimeScales(const Eigen::MatrixXd& dq, const Eigen::VectorXd& time) {
  const Eigen::Index n = dq.rows(), count = dq.cols();
  Eigen::MatrixXd speed(n, count), acceleration(n, count);
  // The regimes' own smoothing, with scales that classify nothing.
  MovingRegimes smoothing;
  smoothing.reset(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n));
  for (Eigen::Index k = 0; k < count; ++k) {
    smoothing.update(time[k], k > 0 ? time[k] - time[k - 1] : 0.0, dq.col(k));
    speed.col(k) = smoothing.velocity();
    acceleration.col(k) = smoothing.acceleration();
  }
  RegimeScales out;
  out.speed.resize(n);
  out.acceleration.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    out.speed[j] = scaleOf(speed.row(j).transpose());
    out.acceleration[j] = scaleOf(acceleration.row(j).transpose());
  }
  return out;
}

void regimeThresholds(const MonitorThresholds& thresholds, const Eigen::VectorXi& regimes,
                      Eigen::VectorXd& out) {
  out = thresholds.values;
  if (thresholds.values_by_regime.size() == 0 || regimes.size() != out.size()) return;
  for (Eigen::Index j = 0; j < out.size(); ++j) {
    const double u = thresholds.values_by_regime(j, regimes[j]);
    if (u > 0.0) out[j] = u;
  }
}

}  // namespace dynid
