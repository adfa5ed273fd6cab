// dynid monitor: an identified model watching a robot's log (or its live samples) for external
// torques. A generalized-momentum observer (needs q, dq and tau only), the direct residual
// tau - tau_hat where the log has ddq, per-joint thresholds from a clean calibration log at a
// chosen false-alarm rate (or from a saved thresholds file), and the events where a residual
// crosses them. Constant memory: a log of any length, or a stream that never ends.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/data.hpp"
#include "core/model.hpp"
#include "core/run_control.hpp"

namespace dynid {

/// The observer's default gain [1/s]: a 10 ms time constant, so a step of external torque shows
/// 99 % of its size within 50 ms.
inline constexpr double kDefaultObserverGain = 100.0;
/// Default false alarms per hour (the whole arm) the calibrated thresholds are set for.
inline constexpr double kDefaultFalseAlarmsPerHour = 0.1;
/// An event ends once every residual has stayed below its threshold this long [s].
inline constexpr double kDefaultEventHold = 0.05;
/// A step between samples longer than this restarts the observer (a gap in the log) [s].
inline constexpr double kDefaultMaxGap = 0.1;

/// The generalized-momentum observer r = K (p - p0 - integral (tau - beta + r) dt), p = M dq,
/// beta = g + tau_f - C^T dq (core/momentum.hpp): r follows the external joint torque through a
/// first-order lag of time constant 1/K per joint. Discretised by the trapezoid rule, solved for
/// r at each sample (stable for any step), so irregular sampling is fine.
class MomentumObserver {
 public:
  /// gain: n entries, each > 0 and finite [1/s] (InputError otherwise). Keeps a reference to model.
  MomentumObserver(const Model& model, const Eigen::VectorXd& gain);
  /// Forgets the past: the next sample starts again with r = 0.
  void restart() { started_ = false; }
  /// Feeds the sample at time t (q, dq, tau: n entries) and returns r [N m]. The first sample
  /// after construction or restart() sets p0 and returns 0; t must increase (asserted).
  const Eigen::VectorXd& update(double t, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const Eigen::Ref<const Eigen::VectorXd>& dq,
                                const Eigen::Ref<const Eigen::VectorXd>& tau);
  const Eigen::VectorXd& residual() const { return r_; }

 private:
  const Model& model_;
  Data data_;
  Eigen::VectorXd gain_, p_, beta_, p0_, integral_, r_, rate_;  // rate_: tau - beta + r
  double t_ = 0.0;
  bool started_ = false;
};

/// A residual's statistics over a clean run, per joint, in constant memory: moments, and the
/// maxima of |r| over blocks of `block` seconds (for the tail).
struct ResidualStatistics {
  Eigen::VectorXd sum_squares, rate_sum_squares, max_abs;   // r^2, (dr/dt)^2 dt-weighted, |r|
  Eigen::VectorXd block_max, block_sum, block_sum_squares;  // this block's max; over blocks
  double rate_time = 0.0;                                   // the time the rate sums cover [s]
  double block = 1.0, block_start = 0.0;                    // [s]
  int blocks = 0;                                           // completed blocks
  long long samples = 0;
  void reset(int n, double block_seconds = 1.0);
  /// One sample at time t; `previous` and dt > 0 when it follows another without a gap.
  void add(double t, const Eigen::VectorXd& r, const Eigen::VectorXd* previous, double dt);
  Eigen::VectorXd rms() const;
  Eigen::VectorXd rateRms() const;  // RMS of dr/dt [N m/s]
};

/// Per-joint thresholds [N m] for `rate` false alarms per second on one joint, the largest of
///   - Rice's formula for the upcrossings of |r| by a stationary Gaussian process of RMS s and
///     rate RMS s': 2 s' / (2 pi s) exp(-u^2 / (2 s^2)) = rate, u = s sqrt(2 ln(s' / (pi s rate)));
///   - the Gumbel law of the block maxima (fitted by moments: beta = sd sqrt(6) / pi,
///     mu = mean - 0.5772 beta), at the probability rate * block of one block exceeding u:
///     u = mu - beta ln(-ln(1 - rate * block)); it follows heavy tails (friction at velocity
///     reversals, model errors) that the Gaussian formula underrates; with 10 blocks or more;
///   - the largest |r| seen in the calibration (a clean run raises no alarm).
Eigen::VectorXd riceThresholds(const ResidualStatistics& statistics, double rate);

/// Which residual raises events.
enum class MonitorResidual { kObserver, kDirect };

/// Thresholds per joint, and where they came from.
struct MonitorThresholds {
  std::string robot;                     // the model's name
  std::vector<std::string> joint_names;  // they must match the monitored robot's
  MonitorResidual residual = MonitorResidual::kObserver;
  Eigen::VectorXd gain;    // the observer gain they were calibrated with [1/s]
  Eigen::VectorXd values;  // [N m]
  std::string source;      // "calibration FILE" or "thresholds FILE"
  double false_alarms_per_hour = kDefaultFalseAlarmsPerHour;
  Eigen::VectorXd calibration_rms, calibration_max;  // of the residual on the calibration run
  double calibration_seconds = 0.0;
};

/// One episode of residuals above their thresholds.
struct MonitorEvent {
  double start = 0.0, end = 0.0;  // [s]: the first sample above, the last before the hold
  std::vector<int> joints;        // the joints (0-based) that crossed their thresholds
  int peak_joint = 0;
  double peak = 0.0, peak_time = 0.0;  // the largest |r| / threshold's |r| [N m], when [s]
  double energy = 0.0;  // the work of the estimated external torque, integral r . dq dt [J]
  bool open = false;    // the data ended (or were stopped) during the event
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

/// A residual's envelope for figures: per joint the min and max over buckets of stride samples,
/// the stride doubling to keep at most 2 kMaxEnvelope buckets. Constant memory.
class ResidualEnvelope {
 public:
  static constexpr int kMaxBuckets = 2048;
  void reset(int n);
  void add(double t, const Eigen::VectorXd& r);
  int count() const { return count_; }
  Eigen::VectorXd time() const { return time_.head(count_); }  // each bucket's first sample
  Eigen::MatrixXd low() const { return low_.leftCols(count_); }
  Eigen::MatrixXd high() const { return high_.leftCols(count_); }

 private:
  Eigen::VectorXd time_;
  Eigen::MatrixXd low_, high_;
  int count_ = 0, stride_ = 1, in_bucket_ = 0;
};

struct MonitorRequest {
  std::string arm;         // an estimate.json, an identified URDF, a dynid JSON model or robot
  std::string robot_spec;  // with an estimate.json: the robot (default: the estimate's)
  std::string data_file;   // a dataset CSV, a recording, or "-" for samples streamed on stdin
  std::string calibration_file;  // a clean dataset CSV or recording to set the thresholds from, or
  std::string thresholds_file;   // a saved thresholds.json (exactly one of the two)
  std::string truth_file;        // simulate --disturbance's ground truth (optional)
  MonitorResidual residual = MonitorResidual::kObserver;
  std::optional<Eigen::VectorXd> gain;  // per joint, or one for all [1/s] (default 100)
  double false_alarms_per_hour = kDefaultFalseAlarmsPerHour;
  double hold = kDefaultEventHold;
  double max_gap = kDefaultMaxGap;
  int threads = 0;
  /// Recordings (ROS bags: .mcap, .db3, .bag or a bag directory; analysis/logs/bag_log.hpp) as
  /// data or calibration: sensor_msgs/JointState with position, velocity and effort, joints matched
  /// by name to the model's. Their JointState topic (empty: the only one), the stamp (header, or
  /// receive time) and the topic whose efforts are the torques when the positions' carry none.
  std::string topic, effort_topic;
  std::string joint_prefix;  // LogSource::joint_prefix
  /// Recordings: the messages' names of the arm's joints, in its joint order (empty: the arm's
  /// own names; else one per joint).
  std::vector<std::string> joint_names = {};
  bool receive_time = false;
  /// Raw efforts that are motor currents (a current-sensing arm's recording or stdin samples):
  /// tau_j = current_j * torque_constants_j * gear_ratios_j [N m/A; gear ratios empty: 1], as
  /// dynid prepare --current. A dataset CSV's tau is taken as it is (prepare converted it); at
  /// least one of the logs must be a recording or stdin. One entry per joint each.
  Eigen::VectorXd torque_constants, gear_ratios;
  MonitorEventSink* sink = nullptr;  // events as they happen (may be null)
  /// Lines streamed from stdin when data_file is "-" (the CLI's reader; tests pass their own).
  std::function<bool(std::string& line)> next_line;
  RunControl control;  // Ctrl-C: stop after the current sample, with the events so far
  /// Throws InputError naming the first option out of range, or for both or neither of the
  /// threshold sources.
  void check() const;
};

struct MonitorOutcome {
  Model model;
  std::string robot_spec;
  MonitorThresholds thresholds;
  std::vector<MonitorEvent> events;
  long long samples = 0;
  double seconds = 0.0;     // from the first sample to the last
  int restarts = 0;         // gaps longer than max_gap
  bool has_direct = false;  // the data carried ddq (files do; stdin may not)
  Eigen::VectorXd observer_rms, observer_max, direct_rms, direct_max;  // over the data
  ResidualEnvelope observer_envelope, direct_envelope;
  std::optional<TruthScore> truth;
  bool interrupted = false;
  std::vector<std::string> warnings;
};

/// Loads the arm, sets the thresholds (a calibration pass or the file), then runs the observer (and
/// the direct residual where ddq is given) over the data, reporting events to request.sink as they
/// start and end. A recording is read whole, its samples taken at their own stamps in time order
/// (repeated stamps dropped, counted in a warning), unfiltered; it has no ddq (observer only).
/// Throws InputError for a bad request, data of another joint count, thresholds of other joints, a
/// recording without the robot's joints or without velocities (prepare it first), or with a
/// non-finite value (naming the file, the sample and the field); ParseError naming the file (or
/// "<stdin>"), line and column for a malformed sample, a non-finite value, time that does not
/// increase or a stream that ends mid-line.
MonitorOutcome monitorRun(const MonitorRequest& request);

/// Reads a thresholds document (kind dynid.monitor_thresholds). Throws ParseError naming the field.
MonitorThresholds readMonitorThresholds(const std::string& file);

/// Parses one streamed sample: "t,q1..qn,dq1..dqn,tau1..taun" (3n + 1 fields) or the dataset row
/// "t,q..,dq..,ddq..,tau.." (4n + 1); the header decides which (`with_ddq`). Throws ParseError
/// naming `source`, the line and the column.
void parseSampleLine(const std::string& line, int n, bool with_ddq, const std::string& source,
                     long long line_number, double& t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
                     Eigen::VectorXd& ddq, Eigen::VectorXd& tau);
/// The streamed header: the dataset header (returns true: with ddq) or t,q..,dq..,tau.. (false).
/// Throws ParseError naming the first column that differs.
bool parseSampleHeader(const std::string& line, int n, const std::string& source);

}  // namespace dynid
