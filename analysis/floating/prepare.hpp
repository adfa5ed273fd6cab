// A floating robot's raw log in, a floating dataset out (`dynid prepare --floating-base`,
// docs/FLOATING.md "From a recording"). Either a ROS bag (data/bags/bag.hpp) with four kinds of
// topic:
//   sensor_msgs/JointState         q, dq when logged, the efforts as joint torques when logged;
//   sensor_msgs/Imu                an IMU on the base body (its header's frame_id a frame of the
//                                  model): orientation, gyro, specific force;
//   geometry_msgs/WrenchStamped    a contact wrench per topic, in its header's frame_id's axes
//                                  about that frame's origin (a frame of the model);
//   std_msgs/Bool                  a contact flag per topic, at the frame the request names for it
//                                  (no header: timed by the recorder's receive time);
// or a table (data/floating/floating_log.hpp: the same signals as named columns, each sensor's
// fields empty in the rows where it has no sample, and contact flags).
// Sensors at different rates, with jitter, are the common case: every signal is resampled
// (linear; a flag held from its last sample) onto one uniform time base over the span all of
// them cover, at the joints' median rate; a step in any signal longer than the gap limit splits
// the log there (no sample is interpolated across it), and each run is then filtered and
// differentiated on its own. Every signal but the flags is low-passed by the same zero-phase
// Butterworth ("parallel filtering": the same lag-free distortion on both sides of
// tau = Y theta); dq is the logged velocity (filtered) or q's derivative, ddq dq's; the base's
// angular acceleration the filtered gyro's derivative; the base's motion then follows the IMU
// rule of data/floating/floating_dataset.hpp (imuBaseMotion).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/floating/floating_model.hpp"
#include "data/floating/floating_dataset.hpp"

namespace dynid {

/// Which topics to read; an empty name: the recording's only topic of that type (several: an
/// InputError naming them).
struct FloatingLogTopics {
  std::string joint_topic, imu_topic;
  /// The WrenchStamped topics; empty: every one the recording has (none: a dataset without
  /// wrenches, e.g. for torques with contact flags).
  std::vector<std::string> wrench_topics;
  /// std_msgs/Bool topics, each a contact flag at a frame of the model (topic -> frame).
  std::map<std::string, std::string> contact_topics;
};

struct FloatingPrepareOptions {
  double rate = 0.0;     // output rate [Hz]; 0: the joint topic's median rate
  double cutoff = -1.0;  // low-pass -3 dB frequency [Hz]; < 0: 10 Hz, or a quarter of the rate
                         // below 40 Hz; 0: none
  int order = 4;         // Butterworth order
  double max_gap = 0.0;  // a topic's step beyond it splits the log [s]; 0: 5 of its median steps
  double trim = -1.0;    // dropped at each run's ends [s]; < 0: 2 / cutoff (none unfiltered)
  bool receive_time = false;  // stamps from the recorder's receive time, not the headers
  /// Contact flags from the wrenches [N]: a wrench's frame holds where the prepared (low-passed)
  /// force's norm reaches it; a frame whose flag the log records keeps that one. 0: none.
  double contact_threshold = 0.0;
  /// Throws InputError naming the field (`rate`, `cutoff`, `order`, `max_gap`, `trim`,
  /// `contact_threshold`) out of
  /// prepare's ranges (core/option_ranges.hpp).
  void check() const;
};

/// What a topic held and how it was read.
struct FloatingTopicSummary {
  std::string topic, type, frame;        // frame: the header's frame_id (Imu, WrenchStamped)
  long long messages = 0, repeated = 0;  // repeated: stamps seen before (dropped)
  double median_step = 0.0;              // [s]
  double gap_limit = 0.0;                // [s]
  int gaps = 0;                          // steps beyond the gap limit
};

struct FloatingPrepareOutcome {
  FloatingDataset dataset;
  std::vector<FloatingTopicSummary> topics;  // joints, IMU, then the wrenches
  double rate = 0.0, cutoff = 0.0, trim = 0.0;
  std::string rate_reason, cutoff_reason;
  /// The span every topic covers [s from the joint topic's first stamp], and the runs kept in it.
  double span_from = 0.0, span_to = 0.0;
  int runs = 0, runs_dropped = 0;  // dropped: too short for the filter's trim
  /// The flags set from the wrenches' force (`contact_threshold`): each frame and the share of the
  /// samples in which it holds.
  std::vector<std::pair<std::string, double>> thresholded;
  double contact_threshold = 0.0;  // [N] the option's value (0: none)
  std::vector<std::string> warnings;
};

/// Reads `path` for `model` (a recording when bags::isBag says so, else a table) and prepares its
/// floating dataset. Throws ParseError for a table's faults (floating_log.hpp) and InputError
/// naming the recording, the topic and what is wrong: topics given for a table, no topic of a
/// needed type or several without a name, a named topic absent or of another type, joints of the
/// model the messages lack, a contact topic's frame the model lacks, an IMU whose orientation is
/// unknown (orientation_covariance[0] = -1) or whose frame_id is not a frame on the base body, a
/// wrench in a frame the model lacks (the frames named) or two topics in one frame, header stamps
/// all zero (use the receive time), topics that never overlap in time, no run long enough to
/// filter, a `contact_threshold` with no wrench to apply it to; ParseError for damage (bags' own).
FloatingPrepareOutcome prepareFloatingLog(const FloatingModel& model, const std::string& path,
                                          const FloatingLogTopics& topics,
                                          const FloatingPrepareOptions& options);

}  // namespace dynid
