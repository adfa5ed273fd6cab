// The GC error of a floating identification's estimates (analysis/floating/gc_measure.hpp): on a
// suspended ANYmal's designed motion at 1 kHz, each estimate rolls the motion out and is compared
// with the model read; independent random states are said not to be a motion.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <memory>

#include "analysis/floating/gc_data.hpp"
#include "analysis/floating/gc_measure.hpp"
#include "analysis/floating/simulate.hpp"
#include "tests/common/floating_datasets.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

using test::designed;
using test::heavier;
using test::twoTilts;

FloatingIdentifyRequest olsOnTorquesAndContacts() {
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;  // noise-free: no channel variance to estimate
  request.sensors = {SensorSet::kTorquesAndContactFlags};
  return request;
}

TEST(FloatingGcMeasure, AnEstimateOfTheRobotThatMadeTheDataRollsOutAsItDoes) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingDataset data = designed(model);
  const FloatingIdentifyOutcome out =
      floatingIdentifyRun(model, olsOnTorquesAndContacts(), data, &data);
  const FloatingGcSummary& gc = out.gc;
  ASSERT_TRUE(gc.refused.empty()) << gc.refused;
  ASSERT_TRUE(gc.validation_refused.empty()) << gc.validation_refused;
  EXPECT_EQ(gc.samples_per_segment, 50);  // 0.05 s at 1 kHz
  EXPECT_NEAR(gc.horizon, 0.05, 1e-12);
  EXPECT_GT(gc.segments, 30);       // 2 s hold 39 segments of 0.05 s
  EXPECT_TRUE(gc.linear_velocity);  // a still base records its zero velocity
  ASSERT_EQ(out.sets.size(), 1u);
  ASSERT_TRUE(out.sets[0].refused.empty()) << out.sets[0].refused;
  // The estimate's base parameters are the model's to 1e-9 and the rest are the model's own: the
  // same rollout to what 1e-9 in the parameters moves it.
  EXPECT_NEAR(out.sets[0].gc_train, gc.model_train, 1e-6 * gc.model_train);
  EXPECT_NEAR(out.sets[0].gc_test, gc.model_test, 1e-6 * gc.model_test);
  // The true model's error is the inputs' 1 ms hold over 50 ms segments.
  EXPECT_LT(gc.model_train, 1e-2) << gc.model_train;
}

TEST(FloatingGcMeasure, SaysHowMuchCloserTheEstimateRollsOutThanTheModelRead) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingModel truth = heavier(model);
  const FloatingDataset data = twoTilts(truth);
  FloatingIdentifyRequest request = olsOnTorquesAndContacts();
  request.sensors = {SensorSet::kTorquesAndWrenches, SensorSet::kTorquesAndContactFlags};
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  ASSERT_TRUE(out.gc.refused.empty()) << out.gc.refused;
  EXPECT_EQ(out.gc.validation_refused, "");  // none given: nothing to refuse
  EXPECT_TRUE(std::isnan(out.gc.model_test));
  ASSERT_EQ(out.sets.size(), 2u);
  for (const FloatingSetEstimate& s : out.sets) ASSERT_TRUE(s.refused.empty()) << s.refused;
  const double robot = floatingGcError(truth, floatingGcData(data, out.contacts), {}).error;
  // The model read, 10 % light, rolls the motion out far worse than the robot that made the data
  // (measured 0.23 against 1.3e-4: the support's wrench carries 10 % more weight than it has).
  EXPECT_GT(out.gc.model_train, 100.0 * robot) << out.gc.model_train << " against " << robot;
  // torques_wrenches' estimate rolls it out as the robot does, to 2 %: its base parameters are
  // drawn with the base still (suspended), and a rollout moves the base a little, reading
  // combinations that stay the model's (measured 0.6 %).
  EXPECT_NEAR(out.sets[0].gc_train, robot, 2e-2 * robot) << out.sets[0].gc_train;
  // torques_contacts eliminates the support's wrench and leaves the 12 combinations only it shows
  // to the model: the robot's values beside the model's lighter ones roll out worse than the
  // model read (measured 6.1): the GC error shows what a set does not determine.
  EXPECT_GT(out.sets[1].gc_train, out.gc.model_train) << out.sets[1].gc_train;
}

/// With noise on the inputs the true model's GC error is the noise's: the floor says so.
TEST(FloatingGcMeasure, TheNoiseFloorIsTheTrueModelsErrorOnNoisyInputs) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingDataset data = twoTilts(model, 0.5);
  FloatingIdentifyRequest request;  // wls: the channels' noise estimated
  request.sensors = {SensorSet::kTorquesAndWrenches};
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  ASSERT_TRUE(out.gc.refused.empty()) << out.gc.refused;
  // Noise-free, the true model's error is the 1 ms hold's (1.3e-4 above); here the noise's.
  EXPECT_GT(out.gc.model_train, 1.0) << out.gc.model_train;
  // The floor estimates it from four draws (measured within 4 % on 30000 samples): 20 % holds
  // the draws' spread on 4000.
  EXPECT_NEAR(out.gc.floor_train, out.gc.model_train, 0.2 * out.gc.model_train)
      << out.gc.floor_train;
  EXPECT_TRUE(std::isnan(out.gc.floor_test));
  // The estimate's own floor, drawn with the same noise: its error is the noise's too.
  EXPECT_NEAR(out.sets[0].gc_floor_train, out.sets[0].gc_train, 0.2 * out.sets[0].gc_train);
  request.method = FloatingMethod::kOls;  // no channel noise estimated: no floor
  EXPECT_TRUE(std::isnan(floatingIdentifyRun(model, request, data).gc.floor_train));
}

/// The support known by its flag alone (no wrench measured): torques_contacts is the set the data
/// feed, and the rollout holds the base where the flag says; the estimate, which determines what
/// the joint torques show with the base held, rolls out as the robot.
TEST(FloatingGcMeasure, FlagsAloneAreRolledOutHeld) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const FloatingModel truth = heavier(model);
  FloatingDataset data = twoTilts(truth);
  data.wrenches.clear();
  FloatingIdentifyRequest request = olsOnTorquesAndContacts();
  request.contacts = {"base:frame"};  // a flag alone does not say it holds the frame, not a point
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  ASSERT_TRUE(out.gc.refused.empty()) << out.gc.refused;
  ASSERT_EQ(out.sets.size(), 1u);
  const double robot = floatingGcError(truth, floatingGcData(data, out.contacts), {}).error;
  // Measured: the robot 1.40e-4 (the hold), the model read 4.04 (its legs 10 % light).
  EXPECT_GT(out.gc.model_train, 100.0 * robot) << out.gc.model_train << " against " << robot;
  // With the base held the rollout reads only what the joint torques determine: the estimate's
  // base parameters are the robot's to 1e-9, its rollout the robot's to what that moves (1e-4).
  EXPECT_NEAR(out.sets[0].gc_train, robot, 1e-4 * robot) << out.sets[0].gc_train;
  // Carried, the support's flag cannot say how it moves the base.
  FloatingIdentifyRequest carried = request;
  carried.motion = FloatingMotion::kCarried;
  EXPECT_TRUE(test::contains(floatingIdentifyRun(model, carried, data).gc.refused,
                             "known by its flag alone"));
}

TEST(FloatingGcMeasure, RandomStatesAreNotAMotion) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  FloatingSimulationOptions options;
  options.samples = 150;
  options.motion = FloatingMotion::kSuspended;
  const FloatingDataset data = simulateFloatingDataset(model, options);
  EXPECT_TRUE(test::contains(floatingMotionRefusal(data), "not one motion"))
      << floatingMotionRefusal(data);
  FloatingIdentifyRequest request = olsOnTorquesAndContacts();
  const FloatingIdentifyOutcome out = floatingIdentifyRun(model, request, data);
  EXPECT_TRUE(test::contains(out.gc.refused, "not one motion")) << out.gc.refused;
  EXPECT_TRUE(std::isnan(out.sets[0].gc_train));
  EXPECT_TRUE(floatingMotionRefusal(designed(model)).empty());
  request.gc.reset();
  EXPECT_EQ(floatingIdentifyRun(model, request, data).gc.refused, "not asked (`gc`)");
}

TEST(FloatingGcMeasure, AnImusDatasetDoesNotRecordTheBasesLinearVelocity) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  FloatingDataset data = designed(model);
  const std::vector<Contact> contacts = contactsOf(model, {"base:frame"});
  EXPECT_TRUE(floatingGcData(data, contacts).linear_velocity);  // still, and recorded so
  data.acceleration.bottomRows<3>().setConstant(0.3);  // accelerating, never moving: unrecorded
  EXPECT_FALSE(floatingGcData(data, contacts).linear_velocity);
  data.acceleration.setZero();
  data.imu_frame = "base";
  EXPECT_FALSE(floatingGcData(data, contacts).linear_velocity);
}

}  // namespace
}  // namespace dynid
