// The monitor's events (analysis/monitor/events.hpp): an episode above the thresholds, held open
// until every residual has been below for `hold`, its joints and peak; and the score against a
// simulation's ground truth.
#include "analysis/monitor/events.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace dynid {
namespace {

TEST(EventDetector, AnEpisodeWithItsJointsPeakAndHold) {
  const Eigen::VectorXd thresholds = Eigen::Vector3d(1.0, 2.0, 10.0);  // kept by reference
  std::vector<MonitorEvent> events;
  EventDetector detector(thresholds, 0.05, nullptr, events);
  const Eigen::Vector3d quiet(0.5, 0.5, 0.5), dq(1.0, 0.0, 0.0);
  const double dt = 0.01;
  double t = 0.0;
  for (; t < 0.1; t += dt) detector.add(t, dt, quiet, dq);
  EXPECT_TRUE(events.empty());
  // Joint 1 crosses at t = 0.1, joint 2 later with the larger residual: the peak.
  detector.add(0.10, dt, Eigen::Vector3d(1.5, 0.5, 0.5), dq);
  detector.add(0.11, dt, Eigen::Vector3d(0.5, 3.0, 0.5), dq);
  detector.add(0.12, dt, Eigen::Vector3d(0.2, 0.2, 0.2), dq);
  // Below for 0.03 s: still open (the hold is 0.05 s); a crossing then extends it.
  detector.add(0.15, dt, quiet, dq);
  EXPECT_TRUE(events.empty());
  detector.add(0.16, dt, Eigen::Vector3d(1.2, 0.0, 0.0), dq);
  for (t = 0.17; t < 0.25; t += dt) detector.add(t, dt, quiet, dq);
  ASSERT_EQ(events.size(), 1u);
  const MonitorEvent& e = events.front();
  EXPECT_DOUBLE_EQ(e.start, 0.10);
  EXPECT_DOUBLE_EQ(e.end, 0.16);
  EXPECT_EQ(e.joints, (std::vector<int>{0, 1}));
  EXPECT_EQ(e.peak_joint, 1);
  EXPECT_EQ(e.contact_link, 1);  // the most distal joint that crossed
  EXPECT_EQ(e.peak, 3.0);
  EXPECT_DOUBLE_EQ(e.peak_time, 0.11);
  EXPECT_FALSE(e.open);
  // A joint below its threshold is not where the event is, however large its residual: the peak
  // is the crossing joint's (a joint-5 push reported peak joint 2 when joint 2 moved fast).
  detector.add(0.26, dt, Eigen::Vector3d(1.1, 1.9, 9.0), dq);
  detector.close();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events.back().peak_joint, 0);
  EXPECT_EQ(events.back().peak, 1.1);
  EXPECT_EQ(events.back().joints, std::vector<int>{0});
  events.clear();
  // The data end during a second event: it is kept, marked open.
  detector.add(0.30, dt, Eigen::Vector3d(0.0, 0.0, 11.0), dq);
  detector.close();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(events.back().open);
  EXPECT_EQ(events.back().joints, std::vector<int>{2});
  EXPECT_EQ(events.back().contact_link, 2);
}

TEST(ScoreEvents, DetectedMissedAndFalseAlarms) {
  std::vector<MonitorEvent> events(3);
  events[0].start = 1.02, events[0].end = 1.3;  // 20 ms after the first episode: detected
  events[1].start = 5.0, events[1].end = 5.1;   // no episode near: a false alarm
  events[2].start = 7.2, events[2].end = 7.4;   // within the third episode but 0.2 s late
  const std::vector<std::pair<double, double>> episodes = {{1.0, 1.2}, {3.0, 3.2}, {7.0, 7.5}};
  const TruthScore score = scoreEvents(episodes, events);
  EXPECT_EQ(score.episodes, 3);
  EXPECT_EQ(score.detected, 1);
  ASSERT_EQ(score.delays.size(), 1u);
  EXPECT_NEAR(score.delays[0], 0.02, 1e-12);  // one subtraction's rounding
  EXPECT_EQ(score.missed_starts, (std::vector<double>{3.0, 7.0}));
  EXPECT_EQ(score.false_alarms, 1);  // the late one overlaps its episode: not a false alarm
}

}  // namespace
}  // namespace dynid
