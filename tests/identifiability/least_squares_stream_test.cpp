#include "identifiability/least_squares_stream.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "tests/common/identification.hpp"

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/regressor.hpp"
#include "data/puma560.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {
namespace {

using test::pumaBase;
using test::pumaTrajectory;

/// The dense reference, independent of the stream: W1 built whole and solved by Householder QR.
struct Dense {
  Eigen::MatrixXd W1;
  Eigen::VectorXd tau;
};

Dense denseOf(const Model& model, const BaseParameters& base, const Trajectory& data) {
  const Observation o = observationFromTrajectory(model, data);
  return {base.baseRegressor(o.W), o.tau};
}

Eigen::VectorXd jointRmsOf(const Eigen::VectorXd& r, int n) {
  const Eigen::Map<const Eigen::MatrixXd> by_joint(r.data(), n, r.size() / n);
  return (by_joint.rowwise().squaredNorm() / static_cast<double>(by_joint.cols())).cwiseSqrt();
}

TEST(LeastSquaresStream, OlsAndWlsEqualTheDenseSolution) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 6.0, 0.5, 3);
  LeastSquaresStream stream(base, 6);
  addTrajectory(stream, puma, data);
  const Dense d = denseOf(puma, base, data);
  // 1e-10 relative: both are backward-stable QR solutions of a system with condition ~1e2-1e3.
  const BaseEstimate ols = stream.estimate(LeastSquaresMethod::kOrdinary);
  const Eigen::VectorXd beta = d.W1.householderQr().solve(d.tau);
  EXPECT_LT((ols.beta - beta).norm(), 1e-10 * beta.norm());
  const Eigen::VectorXd residual = d.tau - d.W1 * beta;
  const Eigen::VectorXd rms = jointRmsOf(residual, 6);
  EXPECT_LT((ols.residual_rms - rms).norm(), 1e-10 * rms.norm());
  EXPECT_LT((ols.measured_rms - jointRmsOf(d.tau, 6)).norm(), 1e-12 * d.tau.norm());
  const double sigma2 = residual.squaredNorm() / static_cast<double>(d.W1.rows() - d.W1.cols());
  const Eigen::MatrixXd covariance = sigma2 * (d.W1.transpose() * d.W1).inverse();
  EXPECT_LT((ols.covariance - covariance).norm(), 1e-8 * covariance.norm());
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(d.W1).singularValues();
  EXPECT_NEAR(ols.condition_number_unscaled, s[0] / s[s.size() - 1],
              1e-9 * ols.condition_number_unscaled);
  EXPECT_NEAR(ols.condition_number, scaledConditionNumber(d.W1), 1e-9 * ols.condition_number);

  // WLS: rows of joint j weighted by 1 / sigma_j from the OLS residuals.
  const BaseEstimate wls = stream.estimate(LeastSquaresMethod::kWeighted);
  const double dof =
      static_cast<double>(data.numSamples()) - static_cast<double>(base.numBase()) / 6;
  Eigen::VectorXd weight(d.W1.rows());
  for (Eigen::Index r = 0; r < weight.size(); ++r)
    weight[r] = 1.0 / std::sqrt(rms[r % 6] * rms[r % 6] * data.numSamples() / dof);
  const Eigen::VectorXd beta_w =
      (weight.asDiagonal() * d.W1).householderQr().solve(weight.asDiagonal() * d.tau);
  EXPECT_LT((wls.beta - beta_w).norm(), 1e-10 * beta_w.norm());
  EXPECT_LT((wls.joint_sigma - ols.joint_sigma).norm(), 1e-14 * ols.joint_sigma.norm());
  EXPECT_LT((wls.residual_rms - jointRmsOf(d.tau - d.W1 * beta_w, 6)).norm(),
            1e-10 * wls.residual_rms.norm());
}

// Rows left out at rest (FitRows) are the dense fit without those rows: the estimate, the
// per-joint statistics over the rows taken and the noise's degrees of freedom.
TEST(LeastSquaresStream, RowsLeftOutAtRestAreTheDenseFitWithoutThem) {
  Model puma = makePuma560(true);  // Coulomb and asymmetry friction: sign(dq)
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 6.0, 0.5, 3);
  // A rest velocity of a fifth of each joint's RMS speed: a tenth of the samples or so at rest.
  puma.rest_velocities.resize(6);
  for (int j = 0; j < 6; ++j)
    puma.rest_velocities[static_cast<std::size_t>(j)] =
        0.2 * std::sqrt(data.dq.row(j).squaredNorm() / data.numSamples());
  const FitRows rows(puma);
  ThreadPool pool(3);
  LeastSquaresStream stream(base, puma);
  stream.addTrajectory(puma, data.samples(0, 2500), &pool, &rows);
  const Trajectory rest_of = data.samples(2500, data.numSamples() - 2500);
  // The second chunk's samples are the set's from 2500 on: FitRows sees them by that index.
  stream.addTrajectory(puma, rest_of, &pool, &rows);
  const Dense all = denseOf(puma, base, data);
  std::vector<Eigen::Index> kept;
  Eigen::VectorXd fitted = Eigen::VectorXd::Zero(6);
  for (Eigen::Index r = 0; r < all.W1.rows(); ++r) {
    const int j = static_cast<int>(r % 6);
    if (std::abs(data.dq(j, r / 6)) > kSignMargin * puma.restVelocity(j)) {
      kept.push_back(r);
      ++fitted[j];
    }
  }
  ASSERT_LT(fitted.maxCoeff(), data.numSamples());  // some rows of every joint were left out
  ASSERT_GT(fitted.minCoeff(), 0.5 * data.numSamples());
  const Eigen::MatrixXd W1 = all.W1(kept, Eigen::all);
  const Eigen::VectorXd tau = all.tau(kept);
  const BaseEstimate ols = stream.estimate(LeastSquaresMethod::kOrdinary);
  EXPECT_EQ(ols.fitted_rows, fitted);
  const Eigen::VectorXd beta = W1.householderQr().solve(tau);
  // 1e-10 relative: both are backward-stable QR solutions of a system with condition ~1e2-1e3.
  EXPECT_LT((ols.beta - beta).norm(), 1e-10 * beta.norm());
  const Eigen::VectorXd residual = tau - W1 * beta;
  Eigen::VectorXd squares = Eigen::VectorXd::Zero(6);
  for (std::size_t i = 0; i < kept.size(); ++i) squares[kept[i] % 6] += residual[i] * residual[i];
  EXPECT_LT((ols.residual_rms - squares.cwiseQuotient(fitted).cwiseSqrt()).norm(),
            1e-10 * ols.residual_rms.norm());
  const double sigma2 = residual.squaredNorm() / static_cast<double>(W1.rows() - W1.cols());
  const Eigen::MatrixXd covariance = sigma2 * (W1.transpose() * W1).inverse();
  EXPECT_LT((ols.covariance - covariance).norm(), 1e-8 * covariance.norm());
  // Without friction that needs sign(dq), nothing is left out.
  const Model rigid = makePuma560(false);
  EXPECT_TRUE(FitRows(rigid).fitted(0, 2, 0.0));
  EXPECT_FALSE(rows.fitted(0, 2, 0.0));
}

TEST(LeastSquaresStream, RankDecisionsEqualTheDenseFactorsOnIllConditionedData) {
  // Short stretches of one motion: the shorter, the closer to collinear the columns (condition
  // numbers from ~1e2 to ~1e7 here), then rank deficient. The stream's verdict per base parameter
  // (|R_jj| of the unit-column factor against the tolerance) equals the dense QR's, and so does
  // the condition number while the data have full rank.
  const Model puma = makePuma560(false);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 4.0, 0.0, 1);
  bool saw_deficient = false, saw_ill = false;
  for (int samples : {4000, 400, 40, 12, 6}) {
    const Trajectory t = data.samples(0, samples);
    LeastSquaresStream stream(base, 6);
    addTrajectory(stream, puma, t);
    const Eigen::MatrixXd W1 = base.baseRegressor(observationFromTrajectory(puma, t).W);
    const Excitation dense = measureExcitation(W1);
    const LeastSquaresStream::Factor f = stream.factor();
    const Excitation streamed = excitationFromRDiagonal(f.r_scaled.diagonal().cwiseAbs());
    EXPECT_EQ(streamed.rank, dense.rank) << samples;
    EXPECT_EQ(streamed.unexcited, dense.unexcited) << samples;
    if (dense.rank < base.numBase()) {
      saw_deficient = true;
      EXPECT_THROW(stream.estimate(LeastSquaresMethod::kOrdinary), NumericalError) << samples;
    } else {
      const BaseEstimate e = stream.estimate(LeastSquaresMethod::kOrdinary);
      const double dense_condition = scaledConditionNumber(W1);
      saw_ill = saw_ill || dense_condition > 1e5;
      // 1e-6 relative: both factor the same columns; the last singular value of a matrix with
      // condition 1e7 carries ~1e-9 relative round-off.
      EXPECT_NEAR(e.condition_number, dense_condition, 1e-6 * dense_condition) << samples;
    }
  }
  EXPECT_TRUE(saw_deficient && saw_ill)
      << "the stretches should span ill-conditioned and deficient";
}

TEST(LeastSquaresStream, RefusesBadSamples) {
  const Model puma = makePuma560(false);
  const BaseParameters base = pumaBase(puma);
  LeastSquaresStream stream(base, 6);
  EXPECT_THROW(stream.add(Eigen::MatrixXd::Zero(5, base.numStandard()), Eigen::VectorXd::Zero(6)),
               InputError);
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(6, base.numStandard());
  Y(2, 3) = std::nan("");
  EXPECT_THROW(stream.add(Y, Eigen::VectorXd::Zero(6)), InputError);
  EXPECT_THROW(stream.estimate(LeastSquaresMethod::kOrdinary), InputError);  // no rows
  Trajectory t = pumaTrajectory(puma, 0.5, 0.0, 1);
  t.dq(2, 17) = std::numeric_limits<double>::infinity();
  try {
    addTrajectory(stream, puma, t);
    FAIL() << "a non-finite sample was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 18"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dq3"), std::string::npos) << e.what();
  }
}

TEST(LeastSquaresStream, TheChainsStructureGivesTheSameEstimateWithSmallerFactors) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 4.0, 0.5, 5);
  LeastSquaresStream dense(base, 6), structured(base, puma);
  addTrajectory(dense, puma, data);
  addTrajectory(structured, puma, data);
  for (LeastSquaresMethod method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    const BaseEstimate a = dense.estimate(method), b = structured.estimate(method);
    // 1e-10 relative: the same least-squares problem, factored in another order (cond ~1e3).
    EXPECT_LT((a.beta - b.beta).norm(), 1e-10 * a.beta.norm());
    EXPECT_LT((a.residual_rms - b.residual_rms).norm(), 1e-10 * a.residual_rms.norm());
    EXPECT_NEAR(a.condition_number, b.condition_number, 1e-9 * a.condition_number);
  }
  // A regressor entry the chain says cannot act (link 1's mass on joint 6) is refused, not
  // silently dropped.
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(6, base.numStandard());
  Y(5, 0) = 1.0;
  EXPECT_THROW(structured.add(Y, Eigen::VectorXd::Zero(6)), Error);
}

TEST(LeastSquaresStream, SameBitsForAnyThreadCountAndChunking) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 3.0, 0.5, 7);
  const auto estimateWith = [&](int threads, int chunk) {
    LeastSquaresStream stream(base, puma);
    ThreadPool pool(threads);
    for (int first = 0; first < data.numSamples(); first += chunk) {
      stream.addTrajectory(puma, data.samples(first, std::min(chunk, data.numSamples() - first)),
                           &pool);
    }
    return stream.estimate(LeastSquaresMethod::kWeighted);
  };
  const BaseEstimate reference = estimateWith(1, data.numSamples());
  for (auto [threads, chunk] : {std::pair{2, 1}, {2, 333}, {3, 1024}, {1, 5000}}) {
    const BaseEstimate e = estimateWith(threads, chunk);
    EXPECT_EQ(e.beta, reference.beta) << threads << " threads, chunks of " << chunk;
    EXPECT_EQ(e.covariance, reference.covariance) << threads << " threads, chunks of " << chunk;
    EXPECT_EQ(e.residual_rms, reference.residual_rms);
  }
  // One sample at a time through add() folds the same rows in the same order.
  LeastSquaresStream single(base, puma);
  Data work(puma);
  for (int k = 0; k < data.numSamples(); ++k)
    single.add(jointTorqueRegressor(puma, work, data.q.col(k), data.dq.col(k), data.ddq.col(k)),
               data.tau.col(k));
  EXPECT_EQ(single.estimate(LeastSquaresMethod::kWeighted).beta, reference.beta);
}

// An estimate in the middle of the stream, then more samples: the second estimate takes every
// sample, as a stream that was only asked at the end does.
TEST(LeastSquaresStream, AnEstimateMidStreamLeavesTheLaterOnesWhole) {
  const Model puma = makePuma560(true);
  const BaseParameters base = pumaBase(puma);
  const Trajectory data = pumaTrajectory(puma, 3.0, 0.5, 11);
  const int half = data.numSamples() / 2 + 37;  // mid-block, so lanes hold partial blocks
  LeastSquaresStream asked_twice(base, puma), asked_once(base, puma);
  asked_twice.addTrajectory(puma, data.samples(0, half));
  const BaseEstimate early = asked_twice.estimate(LeastSquaresMethod::kOrdinary);
  asked_twice.addTrajectory(puma, data.samples(half, data.numSamples() - half));
  asked_once.addTrajectory(puma, data);
  const BaseEstimate late = asked_twice.estimate(LeastSquaresMethod::kOrdinary);
  const BaseEstimate whole = asked_once.estimate(LeastSquaresMethod::kOrdinary);
  EXPECT_EQ(late.num_samples, whole.num_samples);
  // The mid-stream estimate reduced partly filled blocks, so the rows are grouped differently:
  // rounding only.
  EXPECT_LT((late.beta - whole.beta).norm(), 1e-10 * whole.beta.norm());
  EXPECT_LT((late.residual_rms - whole.residual_rms).norm(), 1e-10 * whole.residual_rms.norm());
  EXPECT_GT((early.beta - whole.beta).norm(), 1e-6 * whole.beta.norm());  // the data did differ
  // Sample by sample through add(): the same rows in the same blocks, so the same bits as
  // addTrajectory, the estimate in the middle included.
  LeastSquaresStream one_by_one(base, puma);
  Data work(puma);
  const auto add = [&](int k) {
    one_by_one.add(jointTorqueRegressor(puma, work, data.q.col(k), data.dq.col(k), data.ddq.col(k)),
                   data.tau.col(k));
  };
  for (int k = 0; k < half; ++k) add(k);
  EXPECT_EQ(one_by_one.estimate(LeastSquaresMethod::kOrdinary).beta, early.beta);
  for (int k = half; k < data.numSamples(); ++k) add(k);
  EXPECT_EQ(one_by_one.estimate(LeastSquaresMethod::kOrdinary).beta, late.beta);
}

}  // namespace
}  // namespace dynid
