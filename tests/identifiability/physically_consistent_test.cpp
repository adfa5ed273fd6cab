#include "identifiability/physically_consistent.hpp"

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include "tests/common/identification.hpp"

#include "core/errors.hpp"
#include "core/log_cholesky.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "tests/common/gradient_check.hpp"
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

TEST(PhysicallyConsistent, GradientCheckerOnTheCost) {
  for (bool drives : {false, true}) {
    Model model = consistentChain();
    model.drives_enabled = drives;
    model.offsets_enabled = drives;
    model.finalize();
    const BaseParameters base = pumaBase(model);
    const Observation data =
        observationFromRandomStates(model, 300, 2);  // any rows will do for derivatives
    const Eigen::VectorXd prior = perturbedModel(model, 0.3, 2).standardParameters();
    const PhysicalProblem problem = makePhysicalProblem(base, data, prior, 0.5, 0.1);
    const auto cost = makePhysicalCost(problem);
    // At a point away from the truth, well inside the consistent set (the perturbed model's links,
    // moved inside where needed): at the boundary some derivatives fall below the residuals'
    // round-off and no finite difference can check them.
    Eigen::VectorXd theta = prior;
    for (int i = 0; i < problem.layout.num_links; ++i)
      theta.segment<10>(i * problem.layout.perLink()) =
          nearestConsistent(theta.segment<10>(i * problem.layout.perLink()).eval(), 1e-2);
    const Eigen::VectorXd x = physicalBlocksFromStandard(problem.layout, theta);
    std::vector<Eigen::VectorXd> blocks;
    int offset = 0;
    for (int size : problem.blockSizes()) blocks.push_back(x.segment(offset, size)), offset += size;
    std::string log;
    // Residuals of order 1e2 built from entries of order 1e-4: Ridders' differences carry about
    // 1e-8 relative round-off; 1e-5 leaves room without hiding a wrong derivative.
    EXPECT_TRUE(test::gradientsAgree(*cost, blocks, 1e-5, &log)) << "drives " << drives << log;
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

TEST(PhysicallyConsistent, PriorPullsWhatTheDataCannotSee) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 3.0, 0.5, 7));
  Eigen::VectorXd prior = perturbedModel(model, 0.3, 5).standardParameters();
  for (int i = 0; i < 6; ++i)
    prior.segment<10>(10 * i) = nearestConsistent(prior.segment<10>(10 * i).eval(), 1e-2);
  PhysicalOptions with_prior;
  with_prior.prior_weight = 1.0;
  const PhysicalEstimate free = estimatePhysicallyConsistent(base, train, prior);
  const PhysicalEstimate pulled = estimatePhysicallyConsistent(base, train, prior, with_prior);
  // Closer to the prior in the directions the data cannot see (the null space of W)...
  const Eigen::MatrixXd N = base.nullSpace();
  const Eigen::MatrixXd projector = N * (N.transpose() * N).ldlt().solve(N.transpose());
  EXPECT_LT((projector * (pulled.theta - prior)).norm(), (projector * (free.theta - prior)).norm());
  // ...at little cost in fit: lambda = 1 weighs each parameter's prior like one chi-square unit,
  // so the base parameters move by less than one standard deviation.
  EXPECT_LT(((pulled.beta - free.beta).array() / free.std_dev.array()).abs().maxCoeff(), 1.0);
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

TEST(PhysicallyConsistent, RefusesMismatchedPrior) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 2.0, 0.0, 1));
  EXPECT_THROW(estimatePhysicallyConsistent(base, train, Eigen::VectorXd::Zero(5)), InputError);
}

}  // namespace
}  // namespace dynid
