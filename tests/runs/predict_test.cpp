// dynid predict's run (analysis/runs/predict.hpp) on a filtered log: it reproduces the torque's
// low-pass on the model's friction that needs sign(dq), so that its error is identify's held-out
// error on the same data, and says where the filter came from.
#include "analysis/runs/predict.hpp"

#include <gtest/gtest.h>

#include "analysis/logs/prepare.hpp"
#include "analysis/runs/identify.hpp"
#include "analysis/runs/simulate.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "data/puma560.hpp"
#include "tests/common/error_text.hpp"
#include "tests/common/puma_runs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// The PUMA with its drives' friction, simulated 30 s and through prepare's defaults (10 Hz
/// low-pass), its last quarter held out; the two parts as dataset CSVs (no prepare.json beside).
struct FilteredLog {
  std::string train, validate;
};

FilteredLog filteredPuma() {
  const PrepareOutcome prepared = test::preparedPuma(30.0, 7, 0.25, "predict_filtered_raw.csv");
  FilteredLog out{test::tempPath("predict_filtered_train.csv"),
                  test::tempPath("predict_filtered_validate.csv")};
  writeDatasetCsv(out.train, prepared.train);
  writeDatasetCsv(out.validate, prepared.validate);
  return out;
}

TEST(PredictRun, OnAFilteredLogItsErrorIsIdentifysHeldOutError) {
  const FilteredLog log = filteredPuma();
  const TorqueFilter filter{4, 10.0, 0.0};  // prepare's default, its rate the data's
  IdentifyRequest identify;
  identify.model = makePuma560(true);
  identify.data_file = log.train;
  identify.validate_file = log.validate;
  identify.torque_filter = filter;
  const IdentifyOutcome estimate = identifyRun(identify);
  ASSERT_TRUE(estimate.validation.has_value());
  Model identified = identify.model;
  identified.setStandardParameters(estimate.result.standard);
  PredictRequest request;
  request.model = identified;
  request.data_file = log.validate;
  request.torque_filter = filter;
  // The same comparison as identify's held-out one, with its rest velocities (the training
  // data's; predict measures its own by default): the same sums in another order, 1e-12.
  request.rest_velocity = restThresholds(estimate.rest);
  const PredictOutcome matched = predictRun(request);
  EXPECT_GT(matched.filter_reach, 100);  // 175 samples at 1 kHz
  EXPECT_EQ(matched.torque_filter_source, "given");
  EXPECT_NEAR(matched.prediction.validation.relative_error, estimate.validation->relative_error,
              1e-12 * estimate.validation->relative_error);
  // Without it, the model's own friction steps against a torque whose steps the filter spread.
  request.torque_filter = TorqueFilter{};
  const PredictOutcome plain = predictRun(request);
  EXPECT_EQ(plain.filter_reach, 0);
  EXPECT_EQ(plain.torque_filter_source, "none: given");
  EXPECT_GT(plain.prediction.validation.relative_error,
            1.05 * matched.prediction.validation.relative_error);
  // Auto, with no prepare.json beside the data: unfiltered, and said so.
  request.torque_filter = std::nullopt;
  const PredictOutcome automatic = predictRun(request);
  EXPECT_EQ(automatic.filter_reach, 0);
  EXPECT_NE(automatic.torque_filter_source.find("no prepare.json"), std::string::npos);
  EXPECT_EQ(automatic.prediction.validation.relative_error,
            plain.prediction.validation.relative_error);
  // A cutoff the data's rate cannot carry (500 Hz at 1 kHz) names the file.
  request.torque_filter = TorqueFilter{4, 500.0, 0.0};
  const std::string text = test::errorText<InputError>([&] { predictRun(request); });
  EXPECT_NE(text.find(log.validate), std::string::npos) << text;
}

// The PUMA with its drives sticks and slips at its reversals (26 N m of Coulomb friction through
// the gears on joint 1). There no model predicts the static friction: the true model's error is
// its sensor noise over the rows a fit takes, and the rows at rest are described apart.
TEST(PredictRun, TheTrueModelsErrorIsItsNoiseOverTheRowsAFitTakes) {
  const std::string data = test::tempPath("predict_true_model.csv");
  writeDatasetCsv(data, simulateRun(test::pumaFourier(10.0, 0.05, 2, 0.0)).trajectory);
  PredictRequest request;
  request.model = makePuma560(true);
  request.data_file = data;
  const PredictOutcome o = predictRun(request);
  const Prediction& p = o.prediction;
  ASSERT_EQ(p.compared_rows.size(), 6);
  EXPECT_LT(p.compared_rows[0], 0.95 * p.validation.num_samples);  // joint 1 sticks, and is left
  EXPECT_GT(p.rest.samples[0], 0.05 * p.validation.num_samples);   // out there, described apart
  // 0.05 N m of noise on every joint (10 % covers the RMS's spread over ~9000 rows).
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(p.validation.torque_rms[j], 0.05, 0.005) << j;
}

}  // namespace
}  // namespace dynid
