// The monitor's calibration (analysis/monitor/calibration.hpp) per moving regime: on a geared arm
// whose friction's sign errors at reversals dominate the moving residual, the regimes where the
// model is good get thresholds of their own, and a push there is found below the reversals' error.
#include "analysis/monitor/calibration.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "analysis/monitor/monitor.hpp"
#include "analysis/monitor/regimes.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/puma560.hpp"
#include "tests/common/monitor_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// The PUMA with its published drive model (Coulomb friction up to 25 N m through the gears) and
/// a Stribeck term half of it that the monitored model does not carry, tracking sinusoids of 0.5
/// rad at 0.2-0.6 Hz (joint 1 at 0.2 Hz: fastest at t = 0, 2.5, 5 ... s, reversing at 1.25 s
/// from them), with noise of 0.05 N m and 1e-3 rad/s.
Trajectory gearedPuma(const Model& truth, double duration, std::uint64_t seed,
                      const std::vector<Disturbance>& pushes = {}) {
  TrackingController controller = test::pumaSinusoidController(truth, 0.5, 0.2, 0.6);
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = 0.05;
  options.noise_dq = 1e-3;
  options.seed = seed;
  return simulate(truth, controller, options, pushes);
}

TEST(MonitorCalibration, APushWhereTheModelIsGoodIsFoundBelowTheReversalsError) {
  const Model nominal = makePuma560(true);
  const Model truth = test::withStribeck(nominal);
  const std::string arm = test::tempPath("regimes_arm.json");
  writeFileAtomically(arm, modelToJson(nominal));
  const std::string calibration = test::tempPath("regimes_clean.csv");
  writeDatasetCsv(calibration, gearedPuma(truth, 80.0, 3));
  MonitorRequest request;
  request.arm = arm;
  request.calibration_file = calibration;
  request.data_file = calibration;
  const MonitorOutcome clean = monitorRun(request);
  EXPECT_TRUE(clean.events.empty());  // a clean run raises no alarm
  const MonitorThresholds& th = clean.thresholds;
  ASSERT_EQ(th.values_by_regime.rows(), 6);
  // Joint 1 is slow (below 0.1 of its speed: near its 32 reversals) 6.4 % of the 80 s, too little
  // for a threshold of its own: the single moving threshold, which the friction's sign error
  // there sets, applies. Fast, the model is good and the threshold far lower.
  const int fast = regimeIndex(2, false);
  EXPECT_EQ(th.values_by_regime(0, regimeIndex(0, false)), 0.0);
  EXPECT_EQ(th.values_by_regime(0, regimeIndex(0, true)), 0.0);
  ASSERT_GT(th.values_by_regime(0, fast), 0.0);
  EXPECT_LT(th.values_by_regime(0, fast), 0.25 * th.values[0]);
  // A push on joint 1 at its top speed (t = 30 s), half its single moving threshold and four
  // times its threshold there: found, in the fast regime.
  const double push = 0.5 * th.values[0];
  ASSERT_GT(push, 4.0 * th.values_by_regime(0, fast));
  const std::string pushed = test::tempPath("regimes_pushed.csv");
  writeDatasetCsv(pushed, gearedPuma(truth, 40.0, 4, {test::jointPush(0, push, 30.0, 0.1)}));
  request.data_file = pushed;
  const auto during = [](const MonitorOutcome& o) {
    std::vector<MonitorEvent> out;
    for (const MonitorEvent& e : o.events)
      if (e.end >= 30.0 && e.start <= 30.15) out.push_back(e);
    return out;
  };
  const MonitorOutcome watched = monitorRun(request);
  const std::vector<MonitorEvent> found = during(watched);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_FALSE(found[0].at_rest);
  EXPECT_EQ(found[0].peak_joint, 0);
  EXPECT_EQ(found[0].peak_regime / 2, 2);   // fast (accelerating or not)
  EXPECT_NEAR(found[0].start, 30.0, 0.02);  // the observer's 10 ms
  EXPECT_EQ(watched.events.size(), 1u);     // and nothing else
  // The same thresholds with one moving threshold per joint (the release before the regimes):
  // the push is below it, and unseen.
  MonitorRequest before;
  before.arm = arm;
  before.data_file = pushed;
  before.thresholds_file =
      test::writeThresholdsWithoutRegimes(th, test::tempPath("regimes_v2.json"));
  const MonitorOutcome without = monitorRun(before);
  EXPECT_EQ(without.thresholds.values_by_regime.size(), 0);
  EXPECT_TRUE(during(without).empty());
}

}  // namespace
}  // namespace dynid
