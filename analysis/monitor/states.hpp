// The monitor's arm states: whether the arm holds a pose or moves, from its velocities, and the
// statistic each state is judged by. Moving, the residual itself; at rest, its smoothed change
// from the level it held since the arm came to rest (that level is set by static friction and the
// model's error at the pose, not by a push). Constant memory, one sample at a time.
#pragma once

#include <deque>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace dynid {

// The constants below were chosen on build/bench/bench_monitor --benchmark_filter=MonitorStates
// (docs/MONITOR.md, "The arm states"): the simulated Panda and PUMA 560 with a friction the
// identification does not know, calibrated on another motion, pushes at rest and in motion.

/// The arm is at rest once every joint's smoothed |dq| is within its rest velocity, and settled
/// once it has stayed there this long [s]; settling, only a stirring joint's change that drives
/// its motion counts (StateResidual::update), and the level is taken again once settled. The arm
/// creeps into its static friction after a stop: at 0.2 s the level was taken before the creep
/// ended, and a clean hour of the Panda raised 16 alarms at rest, at 0.5 s none. Before the
/// settling rule a push within 0.5 s of the end of the hunting after a stop was judged moving: 5
/// of the Panda's 80 pushes at rest, with the law's friction as with stick-slip.
inline constexpr double kRestSettleSeconds = 0.5;
/// It leaves rest when a joint's smoothed |dq| exceeds this many rest velocities: a push the
/// controller holds deflects the arm at a few rest velocities; a commanded motion soon exceeds it.
inline constexpr double kRestExitFactor = 5.0;
/// The velocities are smoothed over this time constant before they are compared [s]: white noise
/// of standard deviation sigma then stays within 3 sigma (the rest velocity) at 1 kHz.
inline constexpr double kVelocitySmoothingSeconds = 0.02;
/// At rest, the residual is smoothed over this time constant [s]. The velocity noise reaches the
/// observer's residual unfiltered, as K M sigma_dq, and dominates it at rest on heavy joints (the
/// PUMA's shoulder with its rotor inertia). Smoothed over 30, 50 and 80 ms, the PUMA's threshold
/// at rest on joint 2 was 0.56, 0.40 and 0.28 N m, and its 0.5 N m pushes at rest were found 60,
/// 69 and 75 times in 80. The held residual beta - tau has no such term but carries the
/// controller's reaction to the arm's own motion (4.5 N m on the Panda's joint 2).
inline constexpr double kRestSmoothingSeconds = 0.08;
/// At rest a change counts once it has lasted this long [s]: the statistic is the smallest |change|
/// over the last kRestPersistSeconds (a push lasts; the smoothed noise's excursions above a high
/// level are brief), and the thresholds at rest are learnt on that statistic. A commanded start
/// ramps the torques of joints their static friction still holds until the arm leaves rest, which
/// the residual shows as a change. At 20 ms the starts of the PUMA that sticks set its joint 2's
/// threshold at rest to 0.27 N m (0.04 to 0.06 on its other joints); at 50 ms it was 0.05, and the
/// starts of the clean hour with the law's friction raised 3 alarms, none once a still joint's
/// change stopped counting while the arm stirs (StateResidual::update); at 100 ms the thresholds
/// at rest fell to 0.02 N m and the PUMA's clean hours raised 6 and 2 alarms at rest.
inline constexpr double kRestPersistSeconds = 0.05;
/// The level a push at rest is measured from follows slow drifts (creep into the pose, heating, an
/// integrator) with this time constant [s], and stands still while the change is above half its
/// threshold (a push then keeps its size).
inline constexpr double kRestBaselineSeconds = 0.5;
/// The level stands still at most this long while an event builds [s]: a push can leave the arm
/// held by another static friction, after which the level must follow again.
inline constexpr double kRestFreezeSeconds = 1.0;
/// A calibration needs this much time at rest for thresholds at rest [s] (ten 1 s blocks would
/// give the Gumbel law too; less leaves Rice's formula and the largest value).
inline constexpr double kMinRestSeconds = 2.0;

enum class ArmState { kMoving, kRest };

/// The state machine and the statistic of each state, per sample.
class StateResidual {
 public:
  /// rest_velocity: n entries >= 0 [rad/s or m/s]; empty means no rest state (always moving).
  void reset(const Eigen::VectorXd& rest_velocity);
  /// Forgets the past (a gap in the log): the arm is moving until it settles again.
  void restart();
  /// An event at rest ended at t: a push can leave the arm held by another static friction, so
  /// the arm settles again, its level learnt again once it has been still kRestSettleSeconds.
  void settleAgain(double t);
  /// One sample: time t, step dt (0 after a restart), residual r and velocity dq. `hold_level`:
  /// the change at rest is above half its threshold (an event is building), so the level stands
  /// still. Returns the state; statistic() is r moving; at rest, the smoothed change's smallest
  /// magnitude over the last kRestPersistSeconds, with the sign of the latest change (so that it
  /// crosses a threshold once the change has stayed beyond it that long).
  ArmState update(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq,
                  bool hold_level);
  const Eigen::VectorXd& statistic() const { return statistic_; }
  ArmState state() const { return state_; }
  /// At rest and settling: still for less than kRestSettleSeconds, where only a stirring joint's
  /// change that drives it counts, and the level is taken again once it has settled.
  bool settling() const { return settling_; }
  bool enabled() const { return rest_velocity_.size() > 0; }

 private:
  /// The latest change at rest and, per joint, the (time, |change|) samples that can still be the
  /// window's smallest (a monotonic queue: increasing in both).
  Eigen::VectorXd rest_velocity_, velocity_, smooth_, level_, change_, statistic_;
  std::vector<std::deque<std::pair<double, double>>> window_;
  ArmState state_ = ArmState::kMoving;
  double still_since_ = 0.0, frozen_since_ = 0.0;
  bool still_ = false, fresh_ = true, frozen_ = false, settling_ = false, restarted_ = false;
};

}  // namespace dynid
