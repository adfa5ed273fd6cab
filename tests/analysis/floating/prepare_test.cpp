// A floating robot's recording prepared into a dataset (analysis/floating/prepare.hpp): a robot
// hung from a force-torque sensor on a moving support (tests/common/floating_bag), its joints,
// IMU and sensor recorded at three rates with jittered stamps. The prepared signals meet the
// closed-form motion, the prepared wrench and torques are what inverse dynamics of the prepared
// motion gives (and what a fit leaves of them is the preparation's error), a gap in one topic
// splits the log around it, and what a recording cannot give is refused by name.
#include "analysis/floating/prepare.hpp"

#include <gtest/gtest.h>

#include <sqlite3.h>

#include <cmath>
#include <cstdio>

#include "analysis/floating/gc_data.hpp"
#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/identify.hpp"
#include "analysis/floating/simulate.hpp"
#include "core/errors.hpp"
#include "core/floating/floating_rnea.hpp"
#include "data/io.hpp"
#include "tests/common/floating_bag.hpp"
#include "tests/common/floating_models.hpp"
#include "tests/common/joint_state_db3.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

/// The largest |a - b| over the columns, against b's largest magnitude.
double relativeGap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

struct Prepared {
  FloatingModel model = test::loadExample(test::kAnymalExample);
  test::SuspendedMotion motion;
  FloatingPrepareOutcome out;
  explicit Prepared(const test::SuspendedRecordingOptions& recording = {},
                    bool support_moves = true, const FloatingPrepareOptions& options = {})
      : motion(model, 3, support_moves) {
    const std::string path = test::tempPath("suspended.db3");
    test::writeSuspendedRecording(path, model, motion, recording);
    out = prepareFloatingLog(model, path, {}, options);
  }
};

TEST(FloatingPrepare, ThreeTopicsAtThreeRatesMeetTheMotion) {
  test::SuspendedRecordingOptions recording;
  recording.joint_start = 0.1;  // the joints start later: the span is theirs
  const Prepared p(recording);
  const FloatingDataset& d = p.out.dataset;
  EXPECT_NEAR(p.out.rate, 500.0, 1.0);  // the joints' median step, jittered by 20 %
  EXPECT_EQ(p.out.cutoff, 10.0);
  EXPECT_EQ(p.out.runs, 1);
  ASSERT_EQ(p.out.topics.size(), 3u);
  EXPECT_EQ(p.out.topics[1].frame, "imu_link");
  EXPECT_EQ(p.out.topics[2].frame, "face_rear");
  // The span the joints cover (time counts from their first stamp), less the filter's 0.2 s trim
  // at each end.
  EXPECT_NEAR(d.time[0], 0.2, 2.0 / p.out.rate);
  EXPECT_NEAR(d.time[d.numSamples() - 1], 5.7, 2.0 / p.out.rate);
  ASSERT_TRUE(d.hasTorques());
  ASSERT_EQ(d.wrenches.size(), 1u);
  EXPECT_EQ(d.wrenches[0].frame, "face_rear");
  const int N = d.numSamples(), n = p.model.numJoints();
  Eigen::MatrixXd q(n, N), dq(n, N), ddq(n, N), omega(3, N), alpha(3, N), a0(3, N), R(9, N),
      got_a0(3, N), got_R(9, N);
  for (int k = 0; k < N; ++k) {
    const double t = d.time[k] + recording.joint_start;
    const BaseMotion b = p.motion.base(t);
    q.col(k) = p.motion.q(t);
    dq.col(k) = p.motion.dq(t);
    ddq.col(k) = p.motion.ddq(t);
    omega.col(k) = b.twist.head<3>();
    alpha.col(k) = b.acceleration.head<3>();
    a0.col(k) = p.motion.originAcceleration(t);
    R.col(k) = Eigen::Map<const Eigen::VectorXd>(b.rotation.data(), 9);
    // The prepared twist's v is zero: its derivative is the origin's classical acceleration.
    got_a0.col(k) =
        d.acceleration.col(k).tail<3>() + d.twist.col(k).head<3>().cross(d.twist.col(k).tail<3>());
    const Eigen::Matrix3d got = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    got_R.col(k) = Eigen::Map<const Eigen::VectorXd>(got.data(), 9);
  }
  // Linear interpolation of 400-1000 Hz samples of 0.2-0.6 Hz sines is within h^2/8 |x''| of
  // them (4e-6 of their peak at 400 Hz); a 10 Hz zero-phase low-pass changes them by 1e-10: 1e-4
  // for what is interpolated as it was logged.
  EXPECT_LT(relativeGap(d.q, q), 1e-4);
  EXPECT_LT(relativeGap(d.dq, dq), 1e-4);
  EXPECT_LT(relativeGap(d.twist.topRows<3>(), omega), 1e-4);
  EXPECT_LT(relativeGap(got_R, R), 1e-4);
  // What is differentiated (ddq from dq, the base's angular acceleration from the gyro and the
  // origin's acceleration through it): the interpolation's error changes from sample to sample
  // (the stamps are jittered and the grid's rate is the median step's); differentiated it grows
  // by 1/h, and what the 10 Hz filter leaves of it is 1e-4 to 2e-4 of the peak: 1e-3.
  EXPECT_LT(relativeGap(d.ddq, ddq), 1e-3);
  EXPECT_LT(relativeGap(d.acceleration.topRows<3>(), alpha), 1e-3);
  EXPECT_LT(relativeGap(got_a0, a0), 1e-3);
}

TEST(FloatingPrepare, TheWrenchAndTorquesAreThePreparedMotionsInverseDynamics) {
  const Prepared p;
  const FloatingDataset& d = p.out.dataset;
  FloatingData data(p.model);
  const Pose<double>& S = p.model.findFrame("face_rear")->placement;
  const int N = d.numSamples(), n = p.model.numJoints();
  Eigen::MatrixXd measured(6 + n, N), predicted(6 + n, N);
  for (int k = 0; k < N; ++k) {
    BaseMotion b;
    b.rotation = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    b.twist = d.twist.col(k);
    b.acceleration = d.acceleration.col(k);
    predicted.col(k) = floatingRnea(p.model, data, b, d.q.col(k), d.dq.col(k), d.ddq.col(k));
    // The sensor's wrench about the base origin, in base axes.
    const Eigen::Vector3d n_s = d.wrenches[0].values.col(k).head<3>();
    const Eigen::Vector3d f_s = d.wrenches[0].values.col(k).tail<3>();
    const Eigen::Vector3d f = S.rotation * f_s;
    measured.col(k) << S.rotation * n_s + S.translation.cross(f), f, d.tau.col(k);
  }
  // The signals' own errors (above: 1e-3 for the accelerations) through the dynamics; a frame or
  // sign mistake shows at 1e-1.
  EXPECT_LT(relativeGap(predicted, measured), 1e-3);
  // The prepared motion simulated again, the support carrying the base (its wrench at the base
  // link's origin, in its axes): exactly that inverse dynamics, at the recording's times.
  FloatingSimulationOptions along;
  along.motion = FloatingMotion::kCarried;
  along.motion_from = std::make_shared<const FloatingDataset>(d);
  const FloatingDataset again = simulateFloatingDataset(p.model, along);
  ASSERT_EQ(again.numSamples(), N);
  EXPECT_EQ(again.time, d.time);
  ASSERT_EQ(again.wrenches.size(), 1u);
  EXPECT_EQ(again.wrenches[0].frame, p.model.baseName());
  Eigen::MatrixXd simulated(6 + n, N);
  simulated << again.wrenches[0].values, again.tau;
  EXPECT_LT(relativeGap(simulated, predicted), 1e-12);
}

/// The GC error on the prepared recording (search/floating/floating_gc.hpp): the support turning
/// and moving the base, sensed at face_rear, the joints swinging. The true model, driven by the
/// prepared torques and the sensor's prepared wrench, rolls the prepared motion out close to it
/// (the preparation's 1e-4 errors and the inputs' hold over each 2 ms); a trunk 10 % heavier
/// does not; and the contact must have its wrench.
TEST(FloatingPrepare, TheTrueModelRollsThePreparedMotionOut) {
  const Prepared p;
  const std::vector<Contact> contacts = contactsOf(p.model, {"face_rear:frame"});
  const FloatingGcData data = floatingGcData(p.out.dataset, contacts);
  // From an IMU: the base's linear velocity written as zero while the support carries the base.
  EXPECT_FALSE(data.linear_velocity);
  FloatingGcOptions segments;
  segments.horizon = 0.02;  // ten samples at 500 Hz
  segments.num_segments = 20;
  const FloatingGcResult truth = floatingGcError(p.model, data, segments);
  ASSERT_EQ(truth.starts.size(), 20u);
  FloatingModel heavier = p.model;
  Eigen::VectorXd theta = heavier.standardParameters();
  theta.head<10>() *= 1.1;
  heavier.setStandardParameters(theta);
  const double wrong = floatingGcError(heavier, data, segments).error;
  // The heavier trunk against the sensor's true weight: measured 780 times the truth's 9.3e-5
  // (the truth's a preparation's and a hold's error, of 8.7e-6 a segment at most; 8.1e-4 when
  // the unrecorded linear velocity was compared); 100 times at least.
  EXPECT_GT(wrong, 100.0 * truth.error) << wrong << " against " << truth.error;
  EXPECT_NEAR(truth.horizon, 0.02, 0.5 * 0.002);  // ten periods of about 2 ms
  FloatingDataset flags_only = p.out.dataset;
  flags_only.wrenches.clear();
  try {
    floatingGcData(flags_only, contacts);
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "'face_rear'")) << e.what();
  }
}

/// Contact flags from a wrench: a threshold inside the range of the support's force (the robot's
/// weight and its swinging) flags the sensor's frame where the prepared force reaches it; away
/// from the threshold, the flag is what the force inverse dynamics of the prepared motion needs
/// says (a moment or a frame mistaken shows there), and the share is reported.
TEST(FloatingPrepare, AThresholdOnAWrenchFlagsItsFrameWhereTheForceReachesIt) {
  const Prepared plain;
  ASSERT_TRUE(plain.out.dataset.flags.empty());
  const FloatingDataset& d0 = plain.out.dataset;
  std::vector<double> norms;
  for (int k = 0; k < d0.numSamples(); ++k)
    norms.push_back(d0.wrenches[0].values.col(k).tail<3>().norm());
  std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
  FloatingPrepareOptions options;
  options.contact_threshold = norms[norms.size() / 2];
  const Prepared p({}, true, options);
  const FloatingDataset& d = p.out.dataset;
  ASSERT_EQ(d.flags.size(), 1u);
  EXPECT_EQ(d.flags[0].frame, "face_rear");
  ASSERT_EQ(p.out.thresholded.size(), 1u);
  EXPECT_NEAR(p.out.thresholded[0].second, 0.5, 0.01);  // the median: half the samples
  FloatingData data(p.model);
  const Eigen::Matrix3d S = p.model.findFrame("face_rear")->placement.rotation;
  int compared = 0;
  for (int k = 0; k < d.numSamples(); ++k) {
    BaseMotion b;
    b.rotation = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    b.twist = d.twist.col(k);
    b.acceleration = d.acceleration.col(k);
    const Eigen::VectorXd needed =
        floatingRnea(p.model, data, b, d.q.col(k), d.dq.col(k), d.ddq.col(k));
    const double force = (S.transpose() * needed.segment<3>(3)).norm();
    // The prepared force is inverse dynamics' within 1e-3 (above): 1 % keeps clear of it.
    if (std::abs(force - options.contact_threshold) < 1e-2 * options.contact_threshold) continue;
    ++compared;
    EXPECT_EQ(d.flags[0].holding[static_cast<std::size_t>(k)],
              force >= options.contact_threshold ? 1 : 0)
        << d.time[k];
  }
  EXPECT_GT(compared, d.numSamples() / 2);
  // A table's own flag at the sensor's frame is kept, and said to be.
  const std::string path = test::tempPath("threshold_table.csv");
  test::writeSuspendedTable(path, p.model, p.motion, {});
  const FloatingPrepareOutcome table = prepareFloatingLog(p.model, path, {}, options);
  EXPECT_TRUE(table.thresholded.empty());
  ASSERT_EQ(table.dataset.flags.size(), 1u);
  bool said = false;
  for (const std::string& w : table.warnings)
    said = said || test::contains(w, "leaves the contact flag of face_rear");
  EXPECT_TRUE(said);
  options.contact_threshold = -1.0;
  EXPECT_THROW(prepareFloatingLog(p.model, path, {}, options), InputError);
}

/// A contact switch's std_msgs/Bool topic (no header: timed by its receive time) as a flag at the
/// frame the request names, held between its samples; a frame the model lacks, a topic of another
/// type and contact topics for a table are refused by name.
TEST(FloatingPrepare, ABoolTopicIsAContactFlagAtItsFrame) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const test::SuspendedMotion motion(model, 3);
  test::SuspendedRecordingOptions recording;
  recording.contact_switch = true;
  const std::string path = test::tempPath("switch.db3");
  test::writeSuspendedRecording(path, model, motion, recording);
  FloatingLogTopics topics;
  topics.contact_topics = {{"/contact", "LF_FOOT"}};
  const FloatingPrepareOutcome out = prepareFloatingLog(model, path, topics, {});
  const FloatingDataset& d = out.dataset;
  ASSERT_EQ(d.flags.size(), 1u);
  EXPECT_EQ(d.flags[0].frame, "LF_FOOT");
  ASSERT_EQ(out.topics.size(), 4u);
  EXPECT_EQ(out.topics[3].type, "std_msgs/msg/Bool");
  int checked = 0;
  for (int k = 0; k < d.numSamples(); ++k) {
    if (std::abs(d.time[k] - 3.0) < 2e-3) continue;  // the switch's step, held from 3.0 s
    ++checked;
    EXPECT_EQ(d.flags[0].holding[static_cast<std::size_t>(k)], d.time[k] < 3.0 ? 1 : 0)
        << d.time[k];
  }
  EXPECT_GT(checked, d.numSamples() / 2);
  // A switch that publishes only when it changes: its silences are held, not gaps, and its last
  // message holds to the end (the span and the runs are the sensors').
  recording.switch_on_change = true;
  test::writeSuspendedRecording(path, model, motion, recording);
  const FloatingPrepareOutcome sparse = prepareFloatingLog(model, path, topics, {});
  EXPECT_EQ(sparse.runs, out.runs);
  EXPECT_EQ(sparse.dataset.numSamples(), d.numSamples());
  EXPECT_EQ(sparse.topics[3].gaps, 0);
  for (int k = 0; k < sparse.dataset.numSamples(); ++k) {
    const double t = sparse.dataset.time[k];
    if (std::abs(t - 3.0) < 2e-3 || std::abs(t - 4.5) < 2e-3) continue;
    EXPECT_EQ(sparse.dataset.flags[0].holding[static_cast<std::size_t>(k)],
              t < 3.0 || t > 4.5 ? 1 : 0)
        << t;
  }
  const auto refusal = [&](const FloatingLogTopics& t, const std::string& log) {
    try {
      prepareFloatingLog(model, log, t, {});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("not refused");
  };
  topics.contact_topics = {{"/contact", "LF_PAW"}};
  std::string why = refusal(topics, path);
  EXPECT_TRUE(test::contains(why, "'LF_PAW' is no frame")) << why;
  EXPECT_TRUE(test::contains(why, "`contact_topics`")) << why;
  topics.contact_topics = {{"/ft", "LF_FOOT"}};
  why = refusal(topics, path);
  EXPECT_TRUE(test::contains(why, "not std_msgs/msg/Bool")) << why;
  const std::string table = test::tempPath("switch_table.csv");
  test::writeSuspendedTable(table, model, motion, {});
  why = refusal(topics, table);
  EXPECT_TRUE(test::contains(why, "`contact_topics`")) << why;
}

/// Estimation on a prepared recording of a robot held still by its sensor (the suspended motion
/// class): the base never tilts, so the wrench sets are refused for the one combination that
/// needs gravity from another side, naming the count.
TEST(FloatingPrepare, ASuspendedRecordingIsRefusedWhatAStillBaseCannotShow) {
  const Prepared p({}, /*support_moves=*/false);
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome fit = floatingIdentifyRun(p.model, request, p.out.dataset);
  EXPECT_EQ(fit.motion, FloatingMotion::kSuspended);  // the sensor is on the base body
  ASSERT_EQ(fit.sets.size(), 2u);  // the wrench sets (the recording has no contact flags)
  for (const FloatingSetEstimate& s : fit.sets) {
    SCOPED_TRACE(sensorSetName(s.base.set));
    // A base that never tilts cannot show the whole body's first moment along gravity: only the
    // preparation's errors excite it, far below the rank rule (1e-8 of the most excited), so the
    // set is refused for exactly that one combination, on every compiler (Eigen's default rule,
    // p eps, made it a call at the edge: GCC's build estimated it, clang's refused it).
    std::printf("%s: %s\n", sensorSetName(s.base.set), s.refused.c_str());
    EXPECT_TRUE(test::contains(s.refused, "determine 79 of the 80") ||
                test::contains(s.refused, "determine 91 of the 92"))
        << s.refused;
  }
}

/// The same robot on a support that turns and moves it: identify takes the motion class from the
/// data (the base's RMS angular rate and acceleration, said in a warning), draws the structural
/// base parameters for a carried base (six seconds of one swing do not determine three of them:
/// refused by name), and taken as still the data leave the moving base's inertial forces.
TEST(FloatingPrepare, ACarriedRecordingIsIdentifiedAsCarried) {
  const Prepared moving;
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome fit =
      floatingIdentifyRun(moving.model, request, moving.out.dataset);
  EXPECT_EQ(fit.motion, FloatingMotion::kCarried);
  ASSERT_FALSE(fit.warnings.empty());
  EXPECT_TRUE(test::contains(fit.warnings[0], "its support moves the base (carried) by the data"))
      << fit.warnings[0];
  ASSERT_EQ(fit.sets.size(), 2u);
  for (const FloatingSetEstimate& s : fit.sets) {
    SCOPED_TRACE(sensorSetName(s.base.set));
    // A carried base has 94 combinations; one slow swing excites 91 (the other three at 9e-14 of
    // the most: measured), so the set is refused, naming the count.
    EXPECT_TRUE(test::contains(s.refused, "determine 91 of the 94")) << s.refused;
  }
  // Taken as suspended (a still base's 80 combinations, all excited), the same data leave the
  // moving base's inertial forces unexplained: a residual above the preparation's error (the
  // signals' 1e-4 of their peak, 1e-2 %; measured 0.041 % and 0.23 %).
  request.motion = FloatingMotion::kSuspended;
  const FloatingIdentifyOutcome still =
      floatingIdentifyRun(moving.model, request, moving.out.dataset);
  ASSERT_EQ(still.sets.size(), fit.sets.size());
  for (const FloatingSetEstimate& s : still.sets) {
    SCOPED_TRACE(sensorSetName(s.base.set));
    ASSERT_TRUE(s.refused.empty()) << s.refused;
    EXPECT_GT(s.residual_percent, 1e-2);
  }
  // A support held still is said to be.
  const Prepared held({}, /*support_moves=*/false);
  request.motion.reset();
  const FloatingIdentifyOutcome suspended =
      floatingIdentifyRun(held.model, request, held.out.dataset);
  ASSERT_FALSE(suspended.warnings.empty());
  EXPECT_TRUE(test::contains(suspended.warnings[0], "holds the base still (suspended)"))
      << suspended.warnings[0];
  // An accelerometer's bias (or gravity through an orientation a few degrees off) is constant: a
  // still base with 0.5 m/s^2 of it is still judged still.
  FloatingDataset biased = held.out.dataset;
  biased.acceleration.bottomRows<3>().colwise() += Eigen::Vector3d(0.3, -0.4, 0.0);
  EXPECT_EQ(floatingIdentifyRun(held.model, request, biased).motion, FloatingMotion::kSuspended);
  // A loaded/unloaded pair's other dataset is analysed in the first one's motion class, whatever
  // its own motion would say, so that their base parameters are the same combinations.
  const FloatingIdentifyOutcome paired =
      floatingIdentifyRun(held.model, pairedRequest(request, fit), held.out.dataset);
  EXPECT_EQ(paired.motion, FloatingMotion::kCarried);
  EXPECT_TRUE(paired.warnings.empty());
}

TEST(FloatingPrepare, AGapInOneTopicSplitsTheLogAroundIt) {
  test::SuspendedRecordingOptions recording;
  recording.seconds = 8.0;
  const std::string path = test::tempPath("suspended_gap.db3");
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const test::SuspendedMotion motion(model, 4);
  test::writeSuspendedRecording(path, model, motion, recording);
  // The IMU's messages between 3 and 3.5 s removed, as a dropped connection would (stamps and
  // receive times count from 1 s).
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db,
                         "DELETE FROM messages WHERE topic_id = 2 AND timestamp > 4000000000 AND "
                         "timestamp < 4500000000",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const FloatingPrepareOutcome out = prepareFloatingLog(model, path, {}, {});
  EXPECT_EQ(out.runs, 2);
  EXPECT_EQ(out.topics[1].gaps, 1);
  const FloatingDataset& d = out.dataset;
  for (int k = 0; k < d.numSamples(); ++k)
    EXPECT_FALSE(d.time[k] > 3.0 - 0.2 && d.time[k] < 3.5 + 0.2) << d.time[k];
  for (int k = 1; k < d.numSamples(); ++k) ASSERT_GT(d.time[k], d.time[k - 1]);
  Eigen::MatrixXd q(model.numJoints(), d.numSamples());
  for (int k = 0; k < d.numSamples(); ++k) q.col(k) = motion.q(d.time[k]);
  EXPECT_LT(relativeGap(d.q, q), 1e-4);  // each run filtered on its own: no edge from the gap
}

/// The same sensors in one table, each row one sensor's sample (the others' fields empty), and a
/// contact flag: the same signals as from the recording, the flag held between its samples.
TEST(FloatingPrepare, ATableOfSensorsAtThreeRatesMeetsTheMotion) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const test::SuspendedMotion motion(model, 3);
  const std::string path = test::tempPath("suspended_table.csv");
  test::writeSuspendedTable(path, model, motion, {});
  const FloatingPrepareOutcome out = prepareFloatingLog(model, path, {}, {});
  const FloatingDataset& d = out.dataset;
  ASSERT_EQ(out.topics.size(), 4u);
  EXPECT_EQ(out.topics[0].topic, "q:*");
  EXPECT_EQ(out.topics[1].frame, "imu_link");
  EXPECT_NEAR(out.rate, 500.0, 1.0);
  ASSERT_EQ(d.wrenches.size(), 1u);
  ASSERT_EQ(d.flags.size(), 1u);
  const int N = d.numSamples();
  Eigen::MatrixXd q(model.numJoints(), N), omega(3, N);
  for (int k = 0; k < N; ++k) {
    q.col(k) = motion.q(d.time[k]);
    omega.col(k) = motion.base(d.time[k]).twist.head<3>();
    // The flag's samples (1 kHz) say 1 before 3 s: held, it changes within a millisecond there.
    if (std::abs(d.time[k] - 3.0) > 2e-3) {
      EXPECT_EQ(d.flags[0].holding[static_cast<std::size_t>(k)], d.time[k] < 3.0 ? 1 : 0)
          << d.time[k];
    }
  }
  // As from the recording (above): the same interpolation and filter.
  EXPECT_LT(relativeGap(d.q, q), 1e-4);
  EXPECT_LT(relativeGap(d.twist.topRows<3>(), omega), 1e-4);
}

TEST(FloatingPrepare, ATablesFaultsAreNamedWithTheirLineAndColumn) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const test::SuspendedMotion motion(model, 3);
  test::SuspendedRecordingOptions short_log;
  short_log.seconds = 0.5;
  const std::string path = test::tempPath("table_faults.csv");
  test::writeSuspendedTable(path, model, motion, short_log);
  const std::string text = readFile(path);
  const auto refused = [&](const std::string& table) {
    const std::string bad = test::writeTemp("bad_table.csv", table);
    try {
      prepareFloatingLog(model, bad, {}, {});
    } catch (const ParseError& e) {
      EXPECT_TRUE(test::contains(e.what(), bad)) << e.what();
      return std::string(e.what());
    }
    ADD_FAILURE() << "prepared";
    return std::string();
  };
  // The first row (a joint sample) with its q:LF_HAA field emptied: the line and the column.
  std::string partly = text;
  const std::size_t first = partly.find(',', partly.find('\n')) + 1;
  partly.erase(first, partly.find(',', first) - first);
  const std::string e1 = refused(partly);
  EXPECT_TRUE(test::contains(e1, ":2") && test::contains(e1, "q:LF_HAA")) << e1;
  EXPECT_TRUE(test::contains(e1, "a sensor's sample is all of its fields or none")) << e1;
  std::string ddq = text;
  ddq.replace(ddq.find("dq:LF_HAA"), 9, "ddq:LF_HAA");
  EXPECT_TRUE(test::contains(refused(ddq), "ddq is what a preparation derives"));
  std::string frame = text;
  frame.replace(frame.find("contact:face_rear"), 17, "contact:ft_sensor");
  EXPECT_TRUE(test::contains(refused(frame), "'ft_sensor' is no frame of"));
  std::string twist = text;
  twist.replace(twist.find("base:qw"), 7, "base:wx");
  EXPECT_TRUE(test::contains(refused(twist), "its twist comes from the IMU"));
  // The first IMU row's base:qw set to 2 (after t and every joint's q, dq, tau): its line, the
  // column and the norm.
  std::string scaled;
  int line = 0, bad_line = 0;
  for (std::size_t from = 0; from < text.size(); ++line) {
    const std::size_t end = text.find('\n', from);
    std::string row = text.substr(from, end - from);
    from = end + 1;
    std::vector<std::string> cells;
    for (std::string_view cell : splitFields(row)) cells.emplace_back(cell);
    const std::size_t qw = 1 + 3 * static_cast<std::size_t>(model.numJoints());
    if (line > 0 && bad_line == 0 && !cells[qw].empty()) {
      cells[qw] = "2";
      bad_line = line + 1;
      row.clear();
      for (std::size_t c = 0; c < cells.size(); ++c) row += (c > 0 ? "," : "") + cells[c];
    }
    scaled += row + "\n";
  }
  const std::string e2 = refused(scaled);
  EXPECT_TRUE(test::contains(e2, ":" + std::to_string(bad_line)) && test::contains(e2, "base:qw") &&
              test::contains(e2, "not a unit quaternion"))
      << e2;
}

/// An IMU slower than twice the low-pass is said to be, with its rate; below it, it is not.
TEST(FloatingPrepare, ASlowImuIsSaidToBe) {
  test::SuspendedRecordingOptions recording;
  recording.seconds = 3.0;
  recording.imu_rate = 15.0;
  recording.jitter = 0.0;  // its rate exactly 15 Hz in the message
  const Prepared slow(recording);
  ASSERT_EQ(slow.out.warnings.size(), 1u);
  EXPECT_TRUE(test::contains(slow.out.warnings[0],
                             "/imu is sampled at 15 Hz, below twice the "
                             "10 Hz the dataset keeps (the low-pass)"))
      << slow.out.warnings[0];
  FloatingPrepareOptions low;
  low.cutoff = 5.0;  // below half the IMU's rate: nothing to say
  EXPECT_TRUE(Prepared(recording, true, low).out.warnings.empty());
}

/// prepareFloatingLog's InputError on a recording written with `recording`.
std::string refusal(const test::SuspendedRecordingOptions& recording,
                    const FloatingLogTopics& topics = {}) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const std::string path = test::tempPath("refused.db3");
  test::writeSuspendedRecording(path, model, test::SuspendedMotion(model, 1), recording);
  try {
    prepareFloatingLog(model, path, topics, {});
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), path)) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "prepared";
  return "";
}

TEST(FloatingPrepare, WhatARecordingCannotGiveIsRefusedByName) {
  test::SuspendedRecordingOptions recording;
  recording.seconds = 2.0;
  recording.orientation = false;
  EXPECT_TRUE(test::contains(refusal(recording), "orientation_covariance[0] = -1"));
  recording.orientation = true;
  recording.wrench_frame_id = "ft_sensor";
  const std::string unknown = refusal(recording);
  EXPECT_TRUE(test::contains(unknown, "frame_id 'ft_sensor' is no frame of")) << unknown;
  EXPECT_TRUE(test::contains(unknown, "a wrench in an unknown frame")) << unknown;
  recording.wrench_frame_id.clear();
  recording.imu_frame = "LF_SHANK";
  EXPECT_TRUE(test::contains(refusal(recording), "the IMU's frame 'LF_SHANK' is on a limb"));
  recording.imu_frame = "imu_link";
  recording.joint_start = 1.5;
  recording.imu_end = 1.0;
  EXPECT_TRUE(test::contains(refusal(recording), "the topics never all cover one time"));
  recording.joint_start = 0.0;
  recording.imu_end = -1.0;
  FloatingLogTopics topics;
  topics.imu_topic = "/imu/data";
  const std::string absent = refusal(recording, topics);
  EXPECT_TRUE(test::contains(absent, "no topic '/imu/data' (`imu_topic`)")) << absent;
  EXPECT_TRUE(test::contains(absent, "/imu")) << absent;  // the one there is
  topics.imu_topic = "/ft";
  EXPECT_TRUE(test::contains(refusal(recording, topics), "holds geometry_msgs/msg/WrenchStamped"));
}

}  // namespace
}  // namespace dynid
