#include "analysis/monitor/watch.hpp"

namespace dynid {

Watch::Watch(const MonitorThresholds& thresholds, double hold, MonitorEventSink* sink,
             std::vector<MonitorEvent>& events)
    : thresholds_(thresholds), events_(events), detector_(thresholds.values, hold, sink, events) {
  const Eigen::Index n = thresholds.values.size();
  states_.reset(thresholds.values_at_rest.size() > 0 ? thresholds.rest_velocity
                                                     : Eigen::VectorXd());
  peak_rest_ = peak_moving_ = Eigen::VectorXd::Zero(n);
}

bool Watch::sample(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq) {
  // At rest the level stands still while the change is above half its threshold (building_).
  const bool at_rest = states_.update(t, dt, r, dq, building_) == ArmState::kRest;
  const Eigen::VectorXd& x = states_.statistic();
  const Eigen::VectorXd& limits = at_rest ? thresholds_.values_at_rest : thresholds_.values;
  if (at_rest) rest_seconds_ += dt;
  building_ = at_rest && (x.cwiseAbs().array() > 0.5 * limits.array()).any();
  const std::size_t before = events_.size();
  // At rest the statistic has been beyond its value for kRestPersistSeconds: the start is earlier.
  detector_.add(t, dt, x, dq, limits, at_rest, at_rest ? kRestPersistSeconds : 0.0);
  if (detector_.active()) {
    Eigen::VectorXd& peak = at_rest ? peak_rest_ : peak_moving_;
    peak = peak.cwiseMax(x.cwiseAbs());
  }
  // A push can leave the arm held by another static friction: the level is learnt again.
  if (events_.size() > before && events_.back().at_rest) states_.settleAgain(t);
  return at_rest;
}

}  // namespace dynid
