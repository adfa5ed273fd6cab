#include "analysis/monitor/states.hpp"

#include <algorithm>
#include <cmath>

namespace dynid {

void StateResidual::reset(const Eigen::VectorXd& rest_velocity) {
  rest_velocity_ = rest_velocity;
  restart();
}

void StateResidual::restart() {
  state_ = ArmState::kMoving;
  still_ = settling_ = false;
  fresh_ = true;
}

void StateResidual::settleAgain(double t) {
  if (state_ != ArmState::kRest) return;
  state_ = ArmState::kMoving;
  settling_ = false;
  still_ = true;
  still_since_ = t;
}

ArmState StateResidual::update(double t, double dt, const Eigen::VectorXd& r,
                               const Eigen::VectorXd& dq, bool hold_level) {
  if (!enabled()) {
    statistic_ = r;
    return state_;
  }
  // First-order smoothing, a / (tau + dt) per step: stable for any step.
  const auto smooth = [dt](Eigen::VectorXd& x, const Eigen::VectorXd& to, double tau) {
    x += (dt / (tau + dt)) * (to - x);
  };
  if (fresh_ || dt <= 0.0) {  // the first sample, or after a gap: moving until it settles
    velocity_ = dq;
    smooth_ = r;
    fresh_ = still_ = settling_ = false;
    restarted_ = true;
    state_ = ArmState::kMoving;
  } else {
    smooth(velocity_, dq, kVelocitySmoothingSeconds);
    smooth(smooth_, r, kRestSmoothingSeconds);
  }
  // In units of each joint's rest velocity (a zero one: only an exact zero is at rest).
  double speed = 0.0;
  for (Eigen::Index j = 0; j < dq.size(); ++j) {
    const double v = std::abs(velocity_[j]);
    speed =
        std::max(speed, rest_velocity_[j] > 0.0 ? v / rest_velocity_[j] : (v > 0.0 ? 1e300 : 0));
  }
  if (speed > 1.0) {
    still_ = false;
  } else if (!still_) {
    still_ = true;
    still_since_ = t;
  }
  // Still, the arm is at rest and settles: only a stirring joint's change that drives it counts
  // (below), and the level is taken again once it has been still kRestSettleSeconds (unless an
  // event builds; a push can slip its joint as it settles).
  const bool settled = still_ && t - still_since_ >= kRestSettleSeconds;
  // After a gap the observer starts again from zero: the first rest waits until settled.
  if (speed > kRestExitFactor) restarted_ = false;
  if ((state_ == ArmState::kMoving && still_ && (!restarted_ || settled)) ||
      (settling_ && settled && !frozen_)) {
    restarted_ = false;
    state_ = ArmState::kRest;
    settling_ = !settled;
    level_ = smooth_;
    frozen_ = false;
    window_.assign(static_cast<std::size_t>(r.size()), {});
  } else if (state_ == ArmState::kRest && speed > kRestExitFactor) {
    state_ = ArmState::kMoving;
    settling_ = false;
  }
  if (state_ == ArmState::kMoving) {
    statistic_ = r;
    return state_;
  }
  change_ = smooth_ - level_;
  // The level stands still while an event builds, for at most kRestFreezeSeconds: a push can leave
  // the arm held by another static friction, and the level must then follow.
  if (hold_level && !frozen_) frozen_since_ = t, frozen_ = true;
  if (!hold_level) frozen_ = false;
  if (!frozen_ || t - frozen_since_ > kRestFreezeSeconds)
    smooth(level_, smooth_, kRestBaselineSeconds);
  // The smallest |change| over the window, per joint: a monotonic queue of (time, |change|).
  statistic_.resize(change_.size());
  for (Eigen::Index j = 0; j < change_.size(); ++j) {
    // While the arm settles or stirs (a joint beyond its rest velocity, none beyond the exit), a
    // change counts only on a joint that stirs and where it drives that joint's motion. Friction,
    // the model's error at rest, takes power out of the motion: a change against it is the static
    // friction giving way, and on the joints still held, the controller's torque ramping into their
    // static friction as a commanded start begins. A push that slips its joint does work on it.
    // (The first took the PUMA that sticks from 0.62 to 0.27 N m at rest on joint 2, the second
    // its clean hour with the law's friction from 3 alarms to none: docs/MONITOR.md.)
    if ((settling_ || !still_) &&
        !(std::abs(velocity_[j]) > rest_velocity_[j] && change_[j] * velocity_[j] > 0.0))
      change_[j] = 0.0;
    auto& queue = window_[static_cast<std::size_t>(j)];
    const double size = std::abs(change_[j]);
    while (!queue.empty() && queue.back().second >= size) queue.pop_back();
    queue.emplace_back(t, size);
    while (queue.front().first < t - kRestPersistSeconds) queue.pop_front();
    statistic_[j] = std::copysign(queue.front().second, change_[j]);
  }
  return state_;
}

}  // namespace dynid
