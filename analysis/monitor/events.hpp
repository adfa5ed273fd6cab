// The monitor's events: episodes of residuals above their thresholds (EventDetector), and how
// they compare with a simulation's ground truth (scoreEvents).
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// An event ends once every residual has stayed below its threshold this long [s].
inline constexpr double kDefaultEventHold = 0.05;

/// One episode of residuals above their thresholds.
struct MonitorEvent {
  double start = 0.0, end = 0.0;  // [s]: the first sample above, the last before the hold
  std::vector<int> joints;        // the joints (0-based) that crossed their thresholds
  int peak_joint = 0;             // the joint (0-based) of the peak: one that crossed its threshold
  /// Contact isolation: an external wrench on link k acts on joints 1..k only, so the contact is on
  /// the link of the most distal joint that crossed its threshold, or beyond it (0-based).
  int contact_link = 0;
  double peak = 0.0, peak_time = 0.0;  // its largest |r| while above [N m], and when [s]
  double energy = 0.0;  // the work of the estimated external torque, integral r . dq dt [J]
  bool open = false;    // the data ended (or were stopped) during the event
  /// It started with the arm at rest: judged by the residual's change from its level at rest
  /// (analysis/monitor/states.hpp), whose values `peak` then holds.
  bool at_rest = false;
  /// Moving: the peak joint's regime at the peak (analysis/monitor/regimes.hpp; an index of
  /// kMovingRegimeNames), whose threshold it crossed; -1 at rest or without regimes.
  int peak_regime = -1;
};

/// Receives events as they happen (the stdin mode prints them at once).
class MonitorEventSink {
 public:
  virtual ~MonitorEventSink() = default;
  virtual void started(const MonitorEvent& event) = 0;  // start, joints and peak so far
  virtual void ended(const MonitorEvent& event) = 0;
};

/// How the events compare with the ground truth (dynid simulate --disturbance's file).
struct TruthScore {
  int episodes = 0;                   // runs of samples with a nonzero applied torque
  int detected = 0;                   // episodes an event started within `window` of
  int false_alarms = 0;               // events that overlap no episode (nor `window` after its end)
  std::vector<double> delays;         // per detected episode: event start - episode start [s]
  std::vector<double> missed_starts;  // the episodes not detected
  double window = 0.05;               // [s]
};

/// Whether the residuals are above their thresholds, and the event they make: an event starts at
/// the first sample above and ends once every residual has stayed below for `hold` seconds.
/// Keeps references to `thresholds` and `events`.
class EventDetector {
 public:
  EventDetector(const Eigen::VectorXd& thresholds, double hold, MonitorEventSink* sink,
                std::vector<MonitorEvent>& events)
      : thresholds_(thresholds), hold_(hold), sink_(sink), events_(events) {}

  void add(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq) {
    add(t, dt, r, dq, thresholds_, false);
  }
  /// One sample judged by `thresholds` (the arm state's); `at_rest`: the state is rest. `since`:
  /// the statistic has been beyond its value since that long [s] (a persistence window), so an
  /// event that starts here started that much earlier.
  /// `regimes`: moving, each joint's regime (or null).
  void add(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq,
           const Eigen::VectorXd& thresholds, bool at_rest, double since = 0.0,
           const Eigen::VectorXi* regimes = nullptr) {
    regimes_ = regimes;
    const Eigen::ArrayXd ratio = r.cwiseAbs().array() / thresholds.array();
    const bool above = (ratio > 1.0).any();
    if (!active_) {
      if (!above) return;
      event_ = MonitorEvent{};
      event_.start = t - since;
      event_.end = t;
      event_.at_rest = at_rest;
      active_ = true;
      mark(t, r, ratio);
      if (sink_) sink_->started(event_);
      return;
    }
    event_.energy += r.dot(dq) * dt;
    if (above) {
      mark(t, r, ratio);
      event_.end = t;
      quiet_since_.reset();
      return;
    }
    if (!quiet_since_) quiet_since_ = t;
    if (t - *quiet_since_ >= hold_) finish(false);
  }
  /// The data ended (or were stopped) during an event.
  void close() {
    if (active_) finish(true);
  }
  /// An event is open.
  bool active() const { return active_; }

 private:
  /// The joints above their thresholds join the event; the peak is the largest |r| among them (a
  /// joint below its threshold, however large its residual, is not where the event is).
  void mark(double t, const Eigen::VectorXd& r, const Eigen::ArrayXd& ratio) {
    for (Eigen::Index j = 0; j < r.size(); ++j) {
      if (!(ratio[j] > 1.0)) continue;
      if (std::find(event_.joints.begin(), event_.joints.end(), j) == event_.joints.end())
        event_.joints.push_back(static_cast<int>(j));
      event_.contact_link = std::max(event_.contact_link, static_cast<int>(j));
      if (std::abs(r[j]) > event_.peak) {
        event_.peak = std::abs(r[j]);
        event_.peak_joint = static_cast<int>(j);
        event_.peak_time = t;
        event_.peak_regime = regimes_ ? (*regimes_)[j] : -1;
      }
    }
  }
  void finish(bool open) {
    event_.open = open;
    std::sort(event_.joints.begin(), event_.joints.end());
    event_.contact_link = event_.joints.empty() ? 0 : event_.joints.back();
    events_.push_back(event_);
    if (sink_) sink_->ended(event_);
    active_ = false;
    quiet_since_.reset();
  }
  const Eigen::VectorXd& thresholds_;
  double hold_;
  MonitorEventSink* sink_;
  std::vector<MonitorEvent>& events_;
  bool active_ = false;
  const Eigen::VectorXi* regimes_ = nullptr;  // this sample's
  std::optional<double> quiet_since_;
  MonitorEvent event_;
};

/// One pass over a log: the observer (and the direct residual where ddq is given) at every
/// sample, handed to `visit(t, dt, r_observer, r_direct or null, dq)`; dt = 0 after a restart.

/// Scores `events` against the ground truth's episodes (start, end) [s].
TruthScore scoreEvents(const std::vector<std::pair<double, double>>& episodes,
                       const std::vector<MonitorEvent>& events);

}  // namespace dynid
