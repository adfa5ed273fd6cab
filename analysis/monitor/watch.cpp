#include "analysis/monitor/watch.hpp"

#include <algorithm>
#include <cmath>

namespace dynid {

Watch::Watch(const MonitorThresholds& thresholds, double hold, MonitorEventSink* sink,
             std::vector<MonitorEvent>& events)
    : thresholds_(thresholds), events_(events), detector_(thresholds.values, hold, sink, events) {
  const Eigen::Index n = thresholds.values.size();
  states_.reset(thresholds.values_at_rest.size() > 0 ? thresholds.rest_velocity
                                                     : Eigen::VectorXd());
  peak_rest_ = peak_moving_ = Eigen::VectorXd::Zero(n);
  peak_by_regime_ = Eigen::MatrixXd::Zero(n, kMovingRegimes);
  if (thresholds.values_by_regime.size() > 0)
    regimes_.reset(thresholds.speed_scale, thresholds.acceleration_scale);
  limits_ = thresholds.values;
}

bool Watch::sample(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq) {
  // At rest the level stands still while the change is above half its threshold (building_).
  const bool at_rest = states_.update(t, dt, r, dq, building_) == ArmState::kRest;
  const Eigen::VectorXi& regime = regimes_.update(t, dt, dq);
  const Eigen::VectorXd& x = states_.statistic();
  if (!at_rest) regimeThresholds(thresholds_, regime, limits_);
  const Eigen::VectorXd& limits = at_rest ? thresholds_.values_at_rest : limits_;
  if (at_rest && !states_.settling()) rest_seconds_ += dt;
  building_ = at_rest && (x.cwiseAbs().array() > 0.5 * limits.array()).any();
  const std::size_t before = events_.size();
  // At rest the statistic has been beyond its value for kRestPersistSeconds: the start is earlier.
  detector_.add(t, dt, x, dq, limits, at_rest, at_rest ? kRestPersistSeconds : 0.0,
                !at_rest && regimes_.enabled() ? &regime : nullptr);
  if (detector_.active()) {
    Eigen::VectorXd& peak = at_rest ? peak_rest_ : peak_moving_;
    peak = peak.cwiseMax(x.cwiseAbs());
    if (!at_rest && regimes_.enabled())
      for (Eigen::Index j = 0; j < x.size(); ++j)
        peak_by_regime_(j, regime[j]) = std::max(peak_by_regime_(j, regime[j]), std::abs(x[j]));
  }
  // A push can leave the arm held by another static friction: the level is learnt again.
  if (events_.size() > before && events_.back().at_rest) states_.settleAgain(t);
  return at_rest;
}

}  // namespace dynid
