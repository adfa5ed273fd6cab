// The combined estimator: its gradient, its limits (weight 0 is pc), what it does to both
// criteria, physical consistency along the way, its time budget and its input checks.
#include "search/refinement/combined.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <random>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "core/signal.hpp"
#include "identifiability/physically_consistent.hpp"
#include "search/gc_error.hpp"
#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// A noisy PUMA log, pc from a prior 20 % off the truth, and the pc problem as the torque term.
struct LogCase {
  Model truth = makePuma560();
  Model prior = perturbedModel(truth, 0.2, 5);
  Trajectory data = test::pumaTrajectory(truth, 2.0, 0.5, 3);
  BaseParameters base = test::pumaBase(truth);
  PhysicalEstimate pc = estimatePhysicallyConsistent(base, observationFromTrajectory(truth, data),
                                                     prior.standardParameters());
  GcProblem gc;
  TorqueTerm torque;

  explicit LogCase(int segments = 20) {
    SegmentOptions options = normalisedSegments();
    options.num_segments = segments;
    gc = makeGcProblem(data, options);
    const std::shared_ptr<const PhysicalProblem> problem = pc.problem;
    torque.cost = [problem](const Eigen::VectorXd& theta) { return problem->cost(theta); };
    torque.derivatives = [problem](const Eigen::VectorXd& theta, Eigen::VectorXd* g,
                                   Eigen::MatrixXd* h) { problem->derivatives(theta, g, h); };
    torque.scale = 0.5 * (problem->A * pc.theta - problem->b).squaredNorm() + pc.unexplained;
  }
};

TEST(Combined, GradientMatchesCentralDifferencesOfTheCost) {
  const LogCase s;
  ASSERT_TRUE(s.pc.usable);
  const Eigen::VectorXd& theta = s.pc.theta;
  const double gc = combinedValue(s.truth, s.gc, s.torque, theta, 1.0, 1.0).gc;
  const double g0 = 0.5 * gc;
  // Without a floor, and with one at half the GC error (the log term's gradient included).
  for (const double floor : {0.0, 0.5 * gc}) {
    const Eigen::VectorXd gradient =
        combinedGradient(s.truth, s.gc, s.base.coordinates(), s.torque, theta, 1.0, g0, floor);
    std::mt19937_64 rng(7);
    for (int k = 0; k < 5; ++k) {
      // A direction scaled like the parameters, small enough to stay in the physical set.
      const Eigen::VectorXd d = test::randomVector(rng, static_cast<int>(theta.size()), 1.0)
                                    .cwiseProduct(theta.cwiseAbs().cwiseMax(1e-3));
      const double h = 1e-5;
      const double up = combinedValue(s.truth, s.gc, s.torque, theta + h * d, 1.0, g0, floor).cost;
      const double down =
          combinedValue(s.truth, s.gc, s.torque, theta - h * d, 1.0, g0, floor).cost;
      const double numeric = (up - down) / (2.0 * h);
      const double exact = gradient.dot(d);
      // Central differences of a cost of order 1 with step 1e-5: truncation ~1e-10 times the
      // third derivative, round-off ~1e-16 / 1e-5; 1e-5 relative to the direction's scale
      // catches any wrong term (a missing P, a factor 2, the floor's factor) by orders of
      // magnitude.
      EXPECT_NEAR(exact, numeric,
                  1e-5 * (std::abs(numeric) + gradient.cwiseAbs().dot(d.cwiseAbs())))
          << "direction " << k << ", floor " << floor;
    }
  }
}

TEST(Combined, WeightZeroSolvesThePcProblem) {
  const LogCase s;
  CombinedOptions options;
  options.gc_weight = 0.0;
  options.max_seconds = 0.0;
  options.max_iterations = 200;
  options.function_tolerance = 1e-14;
  const CombinedResult r =
      refineCombined(s.truth, s.gc, s.base.coordinates(), s.torque, s.pc.start_theta, options);
  EXPECT_NE(r.termination.rfind("CONVERGENCE", 0), std::string::npos) << r.termination;
  // The same strictly convex problem from the same start: the base parameters agree to what a
  // relative cost change of 1e-14 leaves (about 1e-7 of each value).
  const Eigen::VectorXd beta = s.base.project(r.theta), expected = s.base.project(s.pc.theta);
  for (Eigen::Index j = 0; j < beta.size(); ++j)
    EXPECT_NEAR(beta[j], expected[j], 1e-5 * std::max(std::abs(expected[j]), 1e-3)) << j;
}

TEST(Combined, TradesTorqueFitForMotionAndStaysConsistent) {
  const LogCase s;
  CombinedOptions options;
  options.max_seconds = 0.0;
  options.noise_floor = false;  // the trade itself (this log's GC error is mostly noise)
  const CombinedResult r =
      refineCombined(s.truth, s.gc, s.base.coordinates(), s.torque, s.pc.theta, options);
  EXPECT_TRUE(r.moved) << r.termination;
  EXPECT_LT(r.final_gc, r.initial_gc);
  // pc minimises the torque term: any other point has a higher one.
  EXPECT_GE(r.final_torque, r.initial_torque);
  EXPECT_LT(r.final_cost, r.initial_cost);
  for (std::size_t k = 1; k < r.history.size(); ++k)
    EXPECT_LT(r.history[k].cost, r.history[k - 1].cost) << "accepted step " << k;
  // F is finite exactly inside the physical set (every pseudo-inertia positive definite).
  EXPECT_TRUE(std::isfinite(s.torque.cost(r.theta)));
}

TEST(Combined, TheNoiseFloorIsTheGcErrorTheTorqueNoiseCauses) {
  // The truth on a log with white torque noise: its GC error is all noise, and the floor
  // estimated from its residuals alone matches it. 40 segments of 8 draws each: the two agree
  // to about 1 / sqrt(40) relative; a factor of 1.5 either way leaves room for that.
  const LogCase s(40);
  const double floor = gcNoiseFloor(s.truth, s.gc, 8, 1);
  ThreadPool pool(1);
  GcWorkspace workspace(1);
  const double truth_gc = gcError(s.truth, s.gc, workspace, pool);
  EXPECT_GT(floor, truth_gc / 1.5);
  EXPECT_LT(floor, truth_gc * 1.5);
  // The same for any thread count; none without noise.
  EXPECT_EQ(gcNoiseFloor(s.truth, s.gc, 8, 2), floor);
  SegmentOptions options = normalisedSegments();
  options.num_segments = 40;
  const GcProblem clean = makeGcProblem(test::pumaTrajectory(s.truth, 2.0, 0.0, 3), options);
  EXPECT_LT(gcNoiseFloor(s.truth, clean, 8, 1), 1e-9 * floor);
}

TEST(Combined, AFilteredLogsNoiseFloorComesFromItsPreparation) {
  // White torque noise of 0.5 N m low-passed at 10 Hz (order 4, zero phase), as dynid prepare
  // filters a log: its first differences see a fiftieth of it, the rollouts all of it. The floor
  // from the residuals' differences misses it; the floor from the noise level and the filter
  // (prepare.json's tau_noise_rms and filter) matches the truth's GC error, to the 1.5 of the
  // white case above.
  const Model truth = makePuma560();
  Trajectory data = test::pumaTrajectory(truth, 2.0, 0.0, 3);
  const double rate = data.meanRate();
  const std::vector<Biquad> filter = butterworthLowPass(4, 10.0, rate);
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal(0.0, 0.5);
  for (int j = 0; j < data.numJoints(); ++j) {
    Eigen::VectorXd noise(data.numSamples());
    for (Eigen::Index k = 0; k < noise.size(); ++k) noise[k] = normal(random);
    data.tau.row(j) += filtfilt(filter, noise).transpose();
  }
  SegmentOptions options = normalisedSegments();
  options.num_segments = 40;
  const GcProblem gc = makeGcProblem(data, options);
  ThreadPool pool(1);
  GcWorkspace workspace(1);
  const double truth_gc = gcError(truth, gc, workspace, pool);
  TorqueNoise noise;
  noise.sigma = Eigen::VectorXd::Constant(truth.numJoints(), 0.5);
  noise.order = 4;
  noise.cutoff = 10.0;
  noise.rate = rate;
  const double prepared = gcNoiseFloor(truth, gc, 8, 1, &noise);
  EXPECT_GT(prepared, truth_gc / 1.5);
  EXPECT_LT(prepared, truth_gc * 1.5);
  EXPECT_LT(gcNoiseFloor(truth, gc, 8, 1), truth_gc / 5.0);
  EXPECT_EQ(gcNoiseFloor(truth, gc, 8, 2, &noise), prepared);  // any thread count
  // A given level without a filter: white noise of that level (four times the floor for twice
  // the level, the rollouts being linear in small noise: 10 % for their curvature).
  noise.order = 0;
  const double white = gcNoiseFloor(truth, gc, 8, 1, &noise);
  noise.sigma *= 2.0;
  EXPECT_NEAR(gcNoiseFloor(truth, gc, 8, 1, &noise), 4.0 * white, 0.1 * 4.0 * white);
  noise.sigma.resize(2);
  EXPECT_THROW(gcNoiseFloor(truth, gc, 8, 1, &noise), InputError);
}

TEST(Combined, DoesNotFitTheGcErrorBelowItsNoiseFloor) {
  // The same noisy log: pc's GC error is at the floor, so the combined estimate stays at pc's.
  const LogCase s;
  CombinedOptions options;
  options.max_seconds = 0.0;
  const CombinedResult r =
      refineCombined(s.truth, s.gc, s.base.coordinates(), s.torque, s.pc.theta, options);
  EXPECT_GT(r.gc_floor, 0.0);
  EXPECT_GE(r.final_gc, 0.9 * std::min(r.gc_floor, r.initial_gc));
  // Its torque term within 1 % of pc's (pc minimises it; the GC term barely pulls).
  EXPECT_LT(r.final_torque, 1.01 * r.initial_torque);
}

TEST(Combined, StopsAtItsTimeBudget) {
  const LogCase s(40);
  CombinedOptions options;
  options.max_seconds = 0.3;
  options.function_tolerance = 0.0;
  options.max_iterations = 1000000;
  options.noise_floor = false;
  const auto t0 = std::chrono::steady_clock::now();
  const CombinedResult r =
      refineCombined(s.truth, s.gc, s.base.coordinates(), s.torque, s.pc.theta, options);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(r.interrupted) << r.termination;
  EXPECT_NE(r.termination.find("time budget"), std::string::npos) << r.termination;
  // Stopped between rollouts: the start's GC evaluation (before the budget counts) and one
  // segment's rollout past the deadline; 1 s covers a loaded machine.
  EXPECT_LT(r.seconds, 0.3 + 1.0);
  EXPECT_LT(wall, 0.3 + 1.0 + 1.0);
  // F is finite exactly inside the physical set (every pseudo-inertia positive definite).
  EXPECT_TRUE(std::isfinite(s.torque.cost(r.theta)));
}

TEST(Combined, RefusesBadInputs) {
  const LogCase s(5);
  const BaseCoordinates coordinates = s.base.coordinates();
  CombinedOptions options;
  EXPECT_THROW(
      refineCombined(s.truth, s.gc, coordinates, s.torque, Eigen::VectorXd::Zero(3), options),
      InputError);
  options.gc_weight = -1.0;
  EXPECT_THROW(refineCombined(s.truth, s.gc, coordinates, s.torque, s.pc.theta, options),
               InputError);
  options.gc_weight = 1.0;
  TorqueTerm bad = s.torque;
  bad.scale = 0.0;
  EXPECT_THROW(refineCombined(s.truth, s.gc, coordinates, bad, s.pc.theta, options), InputError);
  // A start outside the physical set is refused.
  Eigen::VectorXd outside = s.pc.theta;
  outside[0] = -1.0;  // a negative mass
  EXPECT_THROW(refineCombined(s.truth, s.gc, coordinates, s.torque, outside, options), InputError);
}

}  // namespace
}  // namespace dynid
