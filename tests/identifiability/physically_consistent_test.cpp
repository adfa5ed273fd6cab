#include "identifiability/physically_consistent.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "tests/common/identification.hpp"

#include "core/errors.hpp"
#include "core/log_cholesky.hpp"
#include "core/parallel.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::pumaBase;
using test::pumaTrajectory;

bool consistent(const ParameterLayout& layout, const Eigen::VectorXd& theta, int* bad = nullptr) {
  int count = 0;
  for (int i = 0; i < layout.num_links; ++i)
    if (!checkPhysicalConsistency(
             fromStandardVector(theta.segment<10>(i * layout.perLink()).eval()), i, "link")
             .empty())
      ++count;
  if (bad != nullptr) *bad = count;
  return count == 0;
}

/// A physically consistent 6-joint chain (random masses, centres and inertias, with drives), and
/// data from the PUMA's excitation on it.
Model consistentChain() {
  return test::randomTree(4, {.num_bodies = 6, .chain = true, .prismatic = false, .drives = true});
}

TEST(PhysicallyConsistent, DerivativesMatchFiniteDifferences) {
  for (bool drives : {false, true}) {
    Model model = consistentChain();
    if (!drives) model.setDriveTerms(DriveTerms::none());
    const BaseParameters base = pumaBase(model);
    const Observation data = observationFromRandomStates(model, 300, 2);
    const Eigen::VectorXd prior = perturbedModel(model, 0.3, 2).standardParameters();
    const PhysicalProblem problem = makePhysicalProblem(base, data, prior, 0.5, 0.1);
    // At a point inside the physical set, away from the prior: the model's own parameters.
    const Eigen::VectorXd theta = model.standardParameters();
    Eigen::VectorXd gradient;
    Eigen::MatrixXd hessian;
    problem.derivatives(theta, &gradient, &hessian);
    const int p = static_cast<int>(theta.size());
    for (int k = 0; k < p; ++k) {
      // Central differences with h ~ 1e-6 of the entry: truncation ~h^2, round-off ~1e-16 F / h.
      const double h = 1e-6 * std::max(std::abs(theta[k]), 1e-2);
      Eigen::VectorXd up = theta, down = theta;
      up[k] += h, down[k] -= h;
      const double numeric = (problem.cost(up) - problem.cost(down)) / (2 * h);
      EXPECT_NEAR(gradient[k], numeric, 1e-5 * (1.0 + std::abs(numeric)))
          << "drives " << drives << " k " << k;
      Eigen::VectorXd g_up, g_down;
      Eigen::MatrixXd unused;
      problem.derivatives(up, &g_up, &unused);
      problem.derivatives(down, &g_down, &unused);
      const Eigen::VectorXd column = (g_up - g_down) / (2 * h);
      EXPECT_LT((hessian.col(k) - column).cwiseAbs().maxCoeff(),
                1e-5 * (1.0 + column.cwiseAbs().maxCoeff()))
          << "drives " << drives << " k " << k;
    }
    // Outside the physical set the cost is infinite: a negative mass.
    Eigen::VectorXd outside = theta;
    outside[0] = -1.0;
    EXPECT_EQ(problem.cost(outside), std::numeric_limits<double>::infinity());
  }
}

TEST(PhysicallyConsistent, NoiseFreeDataGiveTheTrueBaseParameters) {
  // A consistent truth that fits exactly: no constraint is active, nothing is biased.
  const Model model = consistentChain();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromRandomStates(model, 400, 3);
  const Eigen::VectorXd prior = perturbedModel(model, 0.3, 4).standardParameters();
  const PhysicalEstimate e = estimatePhysicallyConsistent(base, train, prior);
  EXPECT_TRUE(e.usable) << e.termination;
  EXPECT_EQ(e.termination.rfind("CONVERGENCE", 0), 0u) << e.termination;
  const Eigen::VectorXd truth = base.project(model.standardParameters());
  // Exact data: the least-squares optimum is the truth up to the solver's convergence.
  EXPECT_LT(baseParameterError(e.beta, truth), 1e-6);
  EXPECT_TRUE(consistent(model.parameterLayout(), e.theta));
}

TEST(PhysicallyConsistent, ConsistentAtEveryIterateWhereOlsIsNot) {
  // Noisy torques and a short record: the OLS lift breaks the consistency of some links.
  const Model model = makePuma560();
  const ParameterLayout layout = model.parameterLayout();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 3.0, 0.5, 7));
  const Observation test =
      observationFromTrajectory(model, pumaTrajectory(model, 6.0, 0.5, 8, 1.3));
  const Eigen::VectorXd prior = perturbedModel(model, 0.3, 5).standardParameters();
  int iterates = 0, inconsistent_iterates = 0;
  PhysicalOptions options;
  options.on_iterate = [&](const Eigen::VectorXd& theta) {
    ++iterates;
    if (!consistent(layout, theta)) ++inconsistent_iterates;
  };
  const PhysicalEstimate pc = estimatePhysicallyConsistent(base, train, prior, options);
  int ols_bad = 0;
  consistent(layout, base.standardFromBase(pc.ols.beta, prior), &ols_bad);
  EXPECT_GT(ols_bad, 0) << "the scenario should break OLS";
  EXPECT_FALSE(pc.inconsistent_links.empty());
  EXPECT_GT(iterates, 1);
  EXPECT_EQ(inconsistent_iterates, 0);
  EXPECT_TRUE(consistent(layout, pc.theta));
  // Held-out torque RMS within 5 % of OLS's.
  const double ols_rms = validateBaseEstimate(base, pc.ols.beta, test).torque_rms.norm();
  const double pc_rms = validateBaseEstimate(base, pc.beta, test).torque_rms.norm();
  EXPECT_LT(pc_rms, 1.05 * ols_rms) << "OLS " << ols_rms << ", PC " << pc_rms;
  EXPECT_EQ(pc.covariance.rows(), base.numBase());
  EXPECT_TRUE((pc.std_dev.array() > 0).all());
}

TEST(PhysicallyConsistent, ThePriorDecidesWhatTheDataCannotSee) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 3.0, 0.5, 7));
  Eigen::VectorXd prior = perturbedModel(model, 0.3, 5).standardParameters();
  for (int i = 0; i < 6; ++i)
    prior.segment<10>(10 * i) = nearestConsistent(prior.segment<10>(10 * i).eval(), 1e-2);
  // Another prior that differs only in a direction the data cannot see (a null-space vector).
  const Eigen::VectorXd n = base.nullSpace().col(0).normalized();
  const Eigen::VectorXd other = prior + 1e-4 * n;
  ASSERT_LT((base.project(other) - base.project(prior)).norm(), 1e-12);
  const PhysicalEstimate a = estimatePhysicallyConsistent(base, train, prior);
  const PhysicalEstimate b = estimatePhysicallyConsistent(base, train, other);
  EXPECT_EQ(a.termination.rfind("CONVERGENCE", 0), 0u) << a.termination;
  // The data decide the base parameters (well within a standard deviation)...
  EXPECT_LT(((a.beta - b.beta).array() / a.std_dev.array()).abs().maxCoeff(), 1e-2);
  // ...and the prior the unseen direction: the estimate moves with it.
  EXPECT_GT((b.theta - a.theta).dot(n) / 1e-4, 0.5);
  // A heavy prior weight pulls the base parameters toward the prior's, a light one does not.
  PhysicalOptions heavy;
  heavy.prior_weight = 1e4;
  const PhysicalEstimate pulled = estimatePhysicallyConsistent(base, train, prior, heavy);
  const Eigen::VectorXd prior_beta = base.project(prior);
  EXPECT_LT((pulled.beta - prior_beta).norm(), (a.beta - prior_beta).norm());
}

TEST(PhysicallyConsistent, DriveParametersStayNonNegative) {
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 3.0, 2.0, 9));
  const PhysicalEstimate pc = estimatePhysicallyConsistent(base, train, model.standardParameters());
  const ParameterLayout layout = model.parameterLayout();
  for (int i = 0; i < layout.num_links; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_GE(pc.theta[layout.driveIndex(i, k)], 0.0);
}

TEST(PhysicallyConsistent, TheStreamedDataGiveTheDenseEstimate) {
  // The estimate takes only the stream's factors: fed by addTrajectory on two threads in uneven
  // chunks it is the observation's, and its residuals and covariance are the dense formulas'.
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Trajectory data = pumaTrajectory(model, 3.0, 0.5, 7);
  const Observation train = observationFromTrajectory(model, data);
  const Eigen::VectorXd prior = perturbedModel(model, 0.3, 5).standardParameters();
  const PhysicalEstimate dense = estimatePhysicallyConsistent(base, train, prior);
  ThreadPool pool(2);
  LeastSquaresStream stream(base, model);
  for (const auto& [first, count] : {std::pair{0, 700}, {700, 1}, {701, data.numSamples() - 701}})
    stream.addTrajectory(model, data.samples(first, count), &pool);
  const PhysicalEstimate streamed =
      estimatePhysicallyConsistent(base, model.parameterLayout(), stream, prior);
  EXPECT_EQ(streamed.termination.rfind("CONVERGENCE", 0), 0u) << streamed.termination;
  // The two streams hold the same rows but different columns per joint (the model's chain
  // structure or every base column): equal to round-off of the factors, amplified by the
  // Newton solve (cond ~1e4 here); 1e-9 of a standard deviation is far below anything reported.
  EXPECT_LT(((streamed.beta - dense.beta).array() / dense.std_dev.array()).abs().maxCoeff(), 1e-9);
  // Residuals and covariance against the dense formulas on W1 itself (1e-10: round-off of sums
  // of 3000 squares, and of R's inverse at cond ~1e4).
  const Eigen::MatrixXd W1 = base.baseRegressor(train.W);
  const Eigen::VectorXd residual = W1 * streamed.beta - train.tau;
  for (int j = 0; j < 6; ++j) {
    double sum = 0.0;
    for (int k = 0; k < train.num_samples; ++k) sum += residual[6 * k + j] * residual[6 * k + j];
    EXPECT_NEAR(streamed.residual_rms[j], std::sqrt(sum / train.num_samples),
                1e-10 * streamed.residual_rms[j]);
  }
  const double sigma2 = residual.squaredNorm() / (W1.rows() - base.numBase());
  const Eigen::MatrixXd covariance = sigma2 * (W1.transpose() * W1).inverse();
  EXPECT_LT((streamed.covariance - covariance).norm(), 1e-8 * covariance.norm());
}

TEST(PhysicallyConsistent, RefusesMismatchedPrior) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 2.0, 0.0, 1));
  EXPECT_THROW(estimatePhysicallyConsistent(base, train, Eigen::VectorXd::Zero(5)), InputError);
}

}  // namespace
}  // namespace dynid
