#include "analysis/estimation/streaming.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"

#include "analysis/logs/rest.hpp"
#include "analysis/runs/identify.hpp"
#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {
namespace {

TEST(SampleKeeper, KeepsEveryStrideThSampleWhateverTheChunks) {
  const Model puma = makePuma560();
  const Trajectory data = test::pumaTrajectory(puma, 20.0, 0.0, 1);  // 20001 samples at 1 kHz
  for (int chunk : {1, 333, 4096, 20001}) {
    SampleKeeper keeper;
    for (int first = 0; first < data.numSamples(); first += chunk)
      keeper.add(data.samples(first, std::min(chunk, data.numSamples() - first)));
    // 20001 samples: the stride doubles while more than 2 x 4096 would be kept.
    EXPECT_EQ(keeper.stride(), 4) << chunk;
    ASSERT_EQ(keeper.count(), 5001) << chunk;  // samples 0, 4, ..., 20000
    const Trajectory kept = keeper.kept();
    for (int k = 0; k < keeper.count(); k += 250) {
      EXPECT_EQ(kept.time[k], data.time[4 * k]);
      EXPECT_EQ(kept.tau.col(k), data.tau.col(4 * k));
    }
  }
  SampleKeeper few;
  few.add(data.samples(0, 10));
  EXPECT_EQ(few.stride(), 1);
  EXPECT_EQ(few.kept().q, data.q.leftCols(10));
}

// The 95 % band of an OLS estimate covers 95 % of fresh data with the training data's noise, per
// joint; on data three times as noisy it covers about half (the check that fails loudly).
TEST(PredictionBand, CoversNinetyFivePercentOfDataWithTheTrainingNoise) {
  const Model puma = makePuma560(true);
  const Trajectory train = test::pumaTrajectory(puma, 20.0, 0.1, 3);
  const BaseParameters base = structuralBaseParameters(puma);
  LeastSquaresStream stream(base, puma);
  stream.addTrajectory(puma, train);
  const BaseEstimate estimate = stream.estimate(LeastSquaresMethod::kOrdinary);
  Model identified = puma;
  identified.setStandardParameters(base.standardFromBase(estimate.beta, puma.standardParameters()));
  PredictionBand band;
  band.independent = base.independent;
  band.covariance = estimate.covariance;
  band.noise_sigma = estimate.joint_sigma;
  const Prediction fresh = predictTorques(identified, test::pumaTrajectory(puma, 20.0, 0.1, 4, 0.9),
                                          nullptr, nullptr, &band);
  ASSERT_EQ(fresh.band_coverage.size(), 6);
  for (int j = 0; j < 6; ++j) {
    // 20001 samples: the binomial spread of a 95 % coverage is 0.15 %; the estimated noise and
    // parameters move it by a few tenths of a percent more.
    EXPECT_GT(fresh.band_coverage[j], 0.94) << j;
    EXPECT_LT(fresh.band_coverage[j], 0.96) << j;
  }
  EXPECT_EQ(fresh.band.cols(), fresh.time.size());
  const Prediction noisy = predictTorques(identified, test::pumaTrajectory(puma, 20.0, 0.3, 5, 0.9),
                                          nullptr, nullptr, &band);
  // P(|N(0, 3 s)| < 1.96 s) = 0.49.
  for (int j = 0; j < 6; ++j) EXPECT_LT(noisy.band_coverage[j], 0.6) << j;
  const Prediction none = predictTorques(identified, train);
  EXPECT_EQ(none.band_coverage.size(), 0);
}

// The half width from the covariance's lower triangle over the regressor row's entries that are
// not zero equals the whole product z sqrt(diag(W1 Sigma W1^T) + sigma^2), on both robots.
TEST(PredictionBand, HalfWidthIsTheWholeQuadraticForm) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const Model& model : {makePuma560(true), makePanda(true)}) {
    const BaseParameters base = structuralBaseParameters(model);
    const auto b = static_cast<Eigen::Index>(base.independent.size());
    const int n = model.numJoints();
    Eigen::MatrixXd a(b, b);
    for (Eigen::Index k = 0; k < a.size(); ++k) a(k) = normal(rng);
    PredictionBand band;
    band.independent = base.independent;
    band.covariance = 1e-3 * a * a.transpose();
    band.noise_sigma = Eigen::VectorXd::Constant(n, 0.05);
    Data data(model);
    for (int sample = 0; sample < 20; ++sample) {
      Eigen::VectorXd q(n), dq(n), ddq(n);
      for (int j = 0; j < n; ++j) q[j] = normal(rng), dq[j] = normal(rng), ddq[j] = normal(rng);
      const Eigen::VectorXd half = band.halfWidth(model, data, q, dq, ddq);
      const Eigen::MatrixXd Y = jointTorqueRegressor(model, data, q, dq, ddq);
      Eigen::MatrixXd w1(n, b);
      for (Eigen::Index c = 0; c < b; ++c)
        w1.col(c) = Y.col(base.independent[static_cast<std::size_t>(c)]);
      const Eigen::VectorXd whole = band.z * ((w1 * band.covariance * w1.transpose()).diagonal() +
                                              band.noise_sigma.cwiseAbs2())
                                                 .cwiseSqrt();
      // The two sums of b^2 products differ by at most twice the rounding bound of one, 2 b eps
      // |y|^T |Sigma| |y|, which the square root halves relative to its argument.
      const Eigen::VectorXd magnitude =
          (w1.cwiseAbs() * band.covariance.cwiseAbs() * w1.cwiseAbs().transpose()).diagonal();
      for (int j = 0; j < n; ++j) {
        const double bound =
            4.0 * static_cast<double>(b) * std::numeric_limits<double>::epsilon() * magnitude(j);
        EXPECT_NEAR(half[j], whole[j], band.z * band.z * bound / (2.0 * whole[j])) << j;
        EXPECT_GT(half[j], band.z * 0.05);  // the parameters add to the noise
      }
    }
  }
}

TEST(Streaming, PredictFileEqualsThePredictionInMemoryForAnyThreadsAndChunks) {
  const Model puma = makePuma560(true);
  const Trajectory data = test::pumaTrajectory(puma, 3.0, 0.5, 2);
  const std::string path = test::tempPath("stream_predict.csv");
  writeDatasetCsv(path, data);
  Model other = puma;  // another model, so that the residuals are not noise alone
  Eigen::VectorXd theta = other.standardParameters();
  theta *= 1.1;
  other.setStandardParameters(theta);
  const Prediction memory = predictTorques(other, data);
  struct Sink : PredictionSink {
    Eigen::MatrixXd predicted;
    void samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
                 const Eigen::MatrixXd& p) override {
      EXPECT_EQ(time.size(), p.cols());
      EXPECT_EQ(measured.cols(), p.cols());
      predicted.conservativeResize(p.rows(), predicted.cols() + p.cols());
      predicted.rightCols(p.cols()) = p;
    }
  };
  for (int threads : {1, 2, 3})
    for (int chunk : {1, 97, 5000}) {
      ThreadPool pool(threads);
      Sink sink;
      const Prediction p = predictFile(other, path, pool, &sink, chunk);
      // Bit for bit: the same RNEA per sample, the sums taken sample by sample in order.
      EXPECT_EQ(p.validation.torque_rms, memory.validation.torque_rms);
      EXPECT_EQ(p.validation.relative_error, memory.validation.relative_error);
      EXPECT_EQ(p.measured_rms, memory.measured_rms);
      EXPECT_EQ(p.validation.num_samples, data.numSamples());
      EXPECT_EQ(p.predicted, memory.predicted);
      ASSERT_EQ(sink.predicted.cols(), data.numSamples());
      Data work(other);
      for (int k = 0; k < data.numSamples(); k += 500)
        EXPECT_EQ(sink.predicted.col(k),
                  rnea(other, work, data.q.col(k), data.dq.col(k), data.ddq.col(k)));
    }
  EXPECT_GT(memory.validation.relative_error, 0.01);  // the 10 % error in theta shows
}

// The raw comparison interpolates the prediction, never the measurement: a prediction linear in
// time against raw samples on that line gives zero error, wherever the raw stamps fall and however
// the samples arrive in chunks; stamps before, after or across a gap are not compared.
TEST(RawTorqueComparison, InterpolatesThePredictionAtTheRawStampsWithinTheGrid) {
  // Dataset grid: 0, 0.01, ..., 0.1, then a gap, then 0.5, ..., 0.6 (two runs).
  Eigen::VectorXd time(22);
  for (int k = 0; k < 11; ++k) time[k] = 0.01 * k, time[11 + k] = 0.5 + 0.01 * k;
  Eigen::MatrixXd predicted(2, 22);
  for (int k = 0; k < 22; ++k) predicted.col(k) << 3.0 * time[k] + 1.0, -2.0 * time[k];
  RawTorques raw;
  raw.file = "raw.csv";
  // Before the grid, inside run 1 (on and between samples), in the gap, inside run 2, after.
  raw.time.resize(8);
  raw.time << -0.001, 0.0, 0.0037, 0.0991, 0.3, 0.5, 0.5555, 0.7;
  raw.tau.resize(2, 8);
  for (int k = 0; k < 8; ++k) raw.tau.col(k) << 3.0 * raw.time[k] + 1.0, -2.0 * raw.time[k];
  for (int chunk : {1, 5, 22}) {
    RawTorqueComparison comparison(raw);
    for (int first = 0; first < 22; first += chunk) {
      const int m = std::min(chunk, 22 - first);
      comparison.samples(time.segment(first, m), predicted.middleCols(first, m),
                         predicted.middleCols(first, m));
    }
    const Validation v = comparison.result();
    EXPECT_EQ(v.num_samples, 5) << chunk;  // 0, 0.0037, 0.0991, 0.5, 0.5555
    EXPECT_EQ(comparison.skipped(), 3) << chunk;
    EXPECT_LT(v.torque_rms.maxCoeff(), 1e-14) << chunk;  // linear: interpolation is exact
  }
  // A raw sample off the line by 0.5 on joint 1: its residual, over the 5 compared.
  raw.tau(0, 2) += 0.5;
  RawTorqueComparison comparison(raw);
  comparison.samples(time, predicted, predicted);
  EXPECT_NEAR(comparison.result().torque_rms[0], std::sqrt(0.25 / 5.0), 1e-12);
  EXPECT_LT(comparison.result().torque_rms[1], 1e-14);
}

TEST(Streaming, IdentifyGivesTheSameEstimateOnAnyThreadCount) {
  const Model puma = makePuma560(true);
  const std::string path = test::tempPath("stream_identify.csv");
  writeDatasetCsv(path, test::pumaTrajectory(puma, 6.0, 0.5, 3));
  IdentifyRequest request;
  request.model = puma;
  request.data_file = path;
  for (Method method : {Method::kOls, Method::kWls, Method::kPc}) {
    request.method = method;
    request.threads = 1;
    const IdentifyOutcome one = identifyRun(request);
    request.threads = 2;
    const IdentifyOutcome two = identifyRun(request);
    EXPECT_EQ(one.result.standard, two.result.standard);
    EXPECT_EQ(one.result.estimate.beta, two.result.estimate.beta);
    EXPECT_EQ(one.result.estimate.covariance, two.result.estimate.covariance);
    EXPECT_EQ(one.fit.validation.torque_rms, two.fit.validation.torque_rms);
    // The fit's statistics are the least-squares residuals of the rows it took (a joint at rest
    // is left out: its static friction is unknown); RNEA of the identified model on the same
    // rows agrees to round-off (1e-9: torques of ~10 N m, residuals of ~0.5 N m).
    Model identified = puma;
    identified.setStandardParameters(one.result.standard);
    identified.rest_velocities = restThresholds(one.rest);  // the training data's, as identify's
    const Trajectory data = readDatasetCsv(path, 6);
    Eigen::VectorXd squares = Eigen::VectorXd::Zero(6), rows = Eigen::VectorXd::Zero(6);
    Data work(identified);
    for (int k = 0; k < data.numSamples(); ++k) {
      const Eigen::VectorXd r =
          data.tau.col(k) - rnea(identified, work, data.q.col(k), data.dq.col(k), data.ddq.col(k));
      for (int j = 0; j < 6; ++j)
        if (std::abs(data.dq(j, k)) > kSignMargin * identified.restVelocity(j)) {
          squares[j] += r[j] * r[j];
          ++rows[j];
        }
    }
    EXPECT_EQ(one.result.estimate.fitted_rows, rows);
    EXPECT_LT((squares.cwiseQuotient(rows).cwiseSqrt() - one.fit.validation.torque_rms).norm(),
              1e-9 * one.fit.validation.torque_rms.norm());
    EXPECT_EQ(one.fit.predicted.cols(), one.fit.measured.cols());
    EXPECT_EQ(one.fit.time.size(), 6001);  // every sample kept: fewer than 2 x 4096
  }
}

TEST(Streaming, ErrorsNameTheFileAndLineInTheMiddleOfALongFile) {
  const Model puma = makePuma560();
  const std::string path = test::tempPath("stream_bad.csv");
  writeDatasetCsv(path, test::pumaTrajectory(puma, 10.0, 0.0, 1));
  std::string text = readFile(path);
  // Line 7002 (sample 7001): its q3 becomes "x".
  std::size_t at = 0;
  for (int line = 1; line < 7002; ++line) at = text.find('\n', at) + 1;
  std::size_t field = at;
  for (int c = 0; c < 3; ++c) field = text.find(',', field) + 1;
  const std::size_t end = text.find(',', field);
  ASSERT_NE(end, std::string::npos);
  // Spliced rather than string::replace, which trips GCC 12's -Wrestrict false positive.
  text = text.substr(0, field) + "x" + text.substr(end);
  writeFileAtomically(path, text);
  const BaseParameters base = test::pumaBase(puma);
  LeastSquaresStream stream(base, puma);
  ThreadPool pool(2);
  try {
    addDatasetFile(stream, puma, path, pool);
    FAIL() << "expected a ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 7002);
    EXPECT_NE(std::string(e.what()).find("q3: 'x' is not a number"), std::string::npos) << e.what();
  }
}

/// An arm holding a pose for `seconds` at 1 kHz: its velocity white noise of `dq_sigma`, its
/// torque the model's at rest (gravity and offsets, no friction held) plus noise of `tau_sigma`.
Trajectory holdingPose(const Model& model, double seconds, double dq_sigma, double tau_sigma) {
  const int n = model.numJoints(), samples = static_cast<int>(seconds * 1000.0);
  Trajectory out;
  out.resize(n, samples);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Data data(model);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(n, 0.3), zero = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd held = rnea(model, data, q, zero, zero);  // sign(0) = 0: no friction
  for (int k = 0; k < samples; ++k) {
    out.time[k] = k / 1000.0;
    out.q.col(k) = q;
    for (int j = 0; j < n; ++j) {
      out.dq(j, k) = dq_sigma * gauss(rng);
      out.tau(j, k) = held[j] + tau_sigma * gauss(rng);
    }
  }
  return out;
}

TEST(PredictTorques, AtRestTheResidualIsTheSensorNoiseNotCoulombsSign) {
  // The Panda with friction (Fc 0.3..0.9 N m, Fv, Fo) holding a pose; the torque sensor's noise
  // 0.05 N m, the velocity's 1e-4 rad/s. Without a rest velocity the prediction jumps by +-Fc with
  // the sign of the noise; with the one measured from the velocities it does not.
  Model model = makePanda(true);
  for (int j = 0; j < model.numJoints(); ++j) {
    DriveParameters<double> d;
    d[DriveTerm::kCoulomb] = 0.3 + 0.1 * j;
    d[DriveTerm::kViscous] = 0.5;
    d[DriveTerm::kOffset] = 0.2;
    model.setDrive(j, d);
  }
  const Trajectory data = holdingPose(model, 2.0, 1e-4, 0.05);
  const Prediction before = predictTorques(model, data);
  const std::vector<RestVelocity> rest = measureRestVelocities(data.dq, data.time);
  model.rest_velocities = restThresholds(rest);
  const Prediction after = predictTorques(model, data);
  for (int j = 0; j < model.numJoints(); ++j) {
    const double fc = model.drives()[j][DriveTerm::kCoulomb];
    ASSERT_GT(fc, 0.05) << j;
    // 99.7 % of the samples within 3 sigma of zero velocity are at rest; the rest keep a sign.
    EXPECT_GT(after.rest.samples[j], 0.99 * data.numSamples()) << j;
    // The residual's spread at rest: the sensor's 0.05 N m (the few samples outside the rest
    // band still carry +-Fc: 0.3 % of (2 Fc)^2 adds < 10 % for Fc <= 1 N m); before: ~Fc.
    EXPECT_NEAR(after.rest.residual_std[j], 0.05, 0.005) << j;
    EXPECT_GT(before.validation.torque_rms[j], 0.8 * fc) << j;
    // The measured torque lies in the static band (it holds no friction here) but for noise.
    EXPECT_EQ(after.rest.band_lo[j], -fc);
    EXPECT_EQ(after.rest.band_hi[j], fc);
    EXPECT_GT(after.rest.within_band[j], 0.99) << j;
  }
}

}  // namespace
}  // namespace dynid
