// analysis/floating/stand_tilts.hpp: the orientations of a stand for a suspended robot's design.
#include "analysis/floating/stand_tilts.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "analysis/floating/identify.hpp"
#include "analysis/floating/simulate.hpp"
#include "core/errors.hpp"
#include "tests/common/floating_datasets.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

const StandTiltRequest& designRequest(const FloatingModel& model) {
  static const StandTiltRequest request = [&] {
    StandTiltRequest r;
    r.design = test::randomDesign(model, 10.0, 0.4, 3);
    r.samples = 100;
    return r;
  }();
  return request;
}

/// Upright alone the design leaves the support's rows one combination short (79 of the wrenches
/// set's 80: gravity from one side); the chosen orientations determine every set, upright first,
/// each tilt on the grid within max_tilt, and their criterion is no worse than the hand-picked
/// tilts of simulate_test (0.4 rad of roll, then of pitch) on the same grid.
TEST(StandTilts, ChoosesOrientationsThatDetermineWhatUprightCannot) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const StandTiltRequest& request = designRequest(model);
  const StandTiltChoice choice = chooseStandTilts(model, request);
  ASSERT_EQ(choice.tilts.size(), 3u);
  EXPECT_EQ(choice.tilts[0], Eigen::Vector2d::Zero());
  EXPECT_EQ(choice.candidates, 81);
  for (const Eigen::Vector2d& tilt : choice.tilts) {
    EXPECT_LE(tilt.cwiseAbs().maxCoeff(), request.max_tilt + 1e-15);
    const Eigen::Vector2d steps = tilt / (request.max_tilt / 4);  // on the 9-point grid
    EXPECT_NEAR((steps - steps.array().round().matrix()).norm(), 0.0, 1e-12);
  }
  ASSERT_EQ(choice.upright.size(), 3u);
  ASSERT_EQ(choice.chosen.size(), 3u);
  EXPECT_EQ(choice.upright[0].set, SensorSet::kWrenches);
  EXPECT_EQ(choice.upright[0].determined, choice.upright[0].combinations - 1);
  EXPECT_TRUE(std::isinf(choice.upright[0].condition));
  EXPECT_TRUE(std::isinf(choice.condition_added[0]));
  for (const StandSetScore& s : choice.chosen) {
    EXPECT_EQ(s.determined, s.combinations) << sensorSetName(s.set);
    EXPECT_TRUE(std::isfinite(s.condition)) << sensorSetName(s.set);
  }
  // The criterion is the wrenches set's condition number: the report's and the choice's agree (to
  // the eigen- and singular-value routes' round-off).
  EXPECT_NEAR(choice.condition / choice.chosen[0].condition, 1.0, 1e-6);
  // Greedy then exchanges: every step no worse than the last.
  EXPECT_LE(choice.condition_added[2], choice.condition_added[1]);
  EXPECT_LE(choice.condition, choice.condition_added[2]);
  std::printf("chosen: (%g, %g), (%g, %g); condition %g (greedy %g, %d exchanges)\n",
              choice.tilts[1][0], choice.tilts[1][1], choice.tilts[2][0], choice.tilts[2][1],
              choice.condition, choice.condition_added[2], choice.exchanges);
  // The hand-picked tilts of simulate_test, scored the same way: the choice is no worse (the
  // greedy step and the exchanges may stop at another local optimum; on this design they beat it).
  const std::vector<StandSetScore> hand =
      scoreStandTilts(model, request, {{0.0, 0.0}, {0.4, 0.0}, {0.0, 0.4}});
  std::printf("hand-picked: condition %g\n", hand[0].condition);
  EXPECT_LE(choice.condition, hand[0].condition);
  StandTiltRequest one = request;
  one.stands = 1;
  const StandTiltChoice upright_only = chooseStandTilts(model, one);
  EXPECT_EQ(upright_only.tilts.size(), 1u);
  EXPECT_TRUE(std::isinf(upright_only.condition));
}

/// What the choice says is what a simulation at those orientations gives: noise-free, every set
/// is estimated, each to 1e-9 of the model; upright alone the wrench sets are refused.
TEST(StandTilts, ASimulationAtTheChosenTiltsEstimatesEverySet) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const StandTiltRequest& request = designRequest(model);
  const StandTiltChoice choice = chooseStandTilts(model, request);
  FloatingSimulationOptions options;
  options.samples = 100;
  options.motion = FloatingMotion::kSuspended;
  options.trajectory = request.design;
  options.stand_tilts = choice.tilts;
  FloatingIdentifyRequest identify;
  identify.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome out =
      floatingIdentifyRun(model, identify, simulateFloatingDataset(model, options));
  ASSERT_EQ(out.sets.size(), 3u);
  for (const FloatingSetEstimate& s : out.sets) {
    ASSERT_TRUE(s.refused.empty()) << sensorSetName(s.base.set) << ": " << s.refused;
    EXPECT_LT(s.model_error_percent, 1e-7) << sensorSetName(s.base.set);  // 1e-9, in percent
  }
}

TEST(StandTilts, RefusesARequestOutOfRangeByField) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const StandTiltRequest& good = designRequest(model);
  const std::pair<const char*, std::function<void(StandTiltRequest&)>> cases[] = {
      {"`stands`", [](StandTiltRequest& r) { r.stands = 0; }},
      {"`stands`", [](StandTiltRequest& r) { r.stands = kMaxStandChoices + 1; }},
      {"`stands`", [](StandTiltRequest& r) { r.tilt_grid = 3, r.stands = 10; }},
      {"`max_tilt`", [](StandTiltRequest& r) { r.max_tilt = 0.0; }},
      {"`max_tilt`", [](StandTiltRequest& r) { r.max_tilt = std::nan(""); }},
      {"`max_tilt`", [](StandTiltRequest& r) { r.max_tilt = 2.0; }},
      {"`tilt_grid`", [](StandTiltRequest& r) { r.tilt_grid = 4; }},
      {"`tilt_grid`", [](StandTiltRequest& r) { r.tilt_grid = 23; }},
      {"`samples`", [](StandTiltRequest& r) { r.samples = 9; }},
      {"`design`", [](StandTiltRequest& r) { r.design.offset.resize(3); }},
  };
  for (const auto& [field, spoil] : cases) {
    StandTiltRequest request = good;
    spoil(request);
    try {
      chooseStandTilts(model, request);
      ADD_FAILURE() << field << " not refused";
    } catch (const InputError& e) {
      EXPECT_TRUE(test::contains(e.what(), field)) << e.what();
    }
  }
}

}  // namespace
}  // namespace dynid
