#include "identifiability/least_squares.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

BaseParameters pumaBase(const Model& model) {
  const ParameterLayout layout = model.parameterLayout();
  return computeBaseParameters(observationFromRandomStates(model, 150, 1).W,
                               standardParameterNames(layout), 0.0,
                               defaultPreference(layout.num_links, layout.perLink()));
}

/// A well-exciting PUMA trajectory: sinusoids at distinct frequencies around qn.
Trajectory pumaTrajectory(const Model& model, double duration, double noise_tau, std::uint64_t seed,
                          double frequency_scale = 1.0) {
  SinusoidalReference r;
  r.q0 = puma560Pose("qn");
  r.q0[2] = 0.5 * M_PI;  // keep joint 3 away from its limit
  r.amplitude.resize(6);
  r.amplitude << 1.2, 0.8, 0.9, 1.5, 1.2, 1.5;
  r.frequency = Eigen::VectorXd::LinSpaced(6, 0.23, 0.71) * frequency_scale;
  r.phase = Eigen::VectorXd::LinSpaced(6, 0.0, 2.5);
  TrackingController controller(model, r, defaultGains(model, r.q0, 8.0),
                                Eigen::VectorXd::Constant(6, 1e9));
  SimulationOptions options;
  options.duration = duration;
  options.noise_tau = noise_tau;
  options.seed = seed;
  return simulate(model, controller, options);
}

TEST(LeastSquares, NoiseFreeDataGiveTheTrueProjection) {
  for (bool drives : {false, true}) {
    const Model model = makePuma560(drives);
    const BaseParameters base = pumaBase(model);
    const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 10.0, 0.0, 1));
    const Eigen::VectorXd truth = base.project(model.standardParameters());
    for (auto method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
      const BaseEstimate e = estimateBaseParameters(base, train, method);
      // The bound: 1e-8 relative, on the vector (several base values are exact zeros).
      EXPECT_LT((e.beta - truth).norm(), 1e-8 * truth.norm())
          << "drives " << drives << ", " << leastSquaresMethodName(method);
      EXPECT_LT(e.residual_rms.maxCoeff(), 1e-8);
      EXPECT_TRUE(std::isfinite(e.condition_number));
    }
  }
}

TEST(LeastSquares, ReportedSigmaCoversTheErrors) {
  // Torque noise only (noise on q or dq would bias least squares): over seeded trials, at least
  // 95 % of the base-parameter errors lie within 3 reported standard deviations (99.7 % expected
  // for Gaussian estimates).
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Eigen::VectorXd truth = base.project(model.standardParameters());
  for (auto method : {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    int within = 0, total = 0;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const Observation train =
          observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.05, seed));
      const BaseEstimate e = estimateBaseParameters(base, train, method);
      for (int j = 0; j < base.numBase(); ++j, ++total)
        if (std::abs(e.beta[j] - truth[j]) <= 3.0 * e.std_dev[j]) ++within;
    }
    EXPECT_GE(within, 0.95 * total)
        << leastSquaresMethodName(method) << ": " << within << "/" << total;
  }
}

TEST(LeastSquares, ValidationOnHeldOutData) {
  const Model model = makePuma560(true);
  const BaseParameters base = pumaBase(model);
  const Observation train = observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.02, 1));
  const Observation test =
      observationFromTrajectory(model, pumaTrajectory(model, 5.0, 0.0, 2, 1.3));
  const BaseEstimate e = estimateBaseParameters(base, train, LeastSquaresMethod::kWeighted);
  const Validation v = validateBaseEstimate(base, e.beta, test);
  ASSERT_EQ(v.torque_rms.size(), 6);
  // Noise of 0.02 N m on 5000 samples leaves prediction errors far below the noise.
  EXPECT_LT(v.torque_rms.maxCoeff(), 0.02);
  EXPECT_LT(v.normalised_rms.maxCoeff(), 0.05);
  // The torque noise estimated per joint is close to the simulated 0.02 N m.
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(e.joint_sigma[j], 0.02, 0.002) << j;
}

TEST(LeastSquares, RefusesRankDeficientData) {
  const Model model = makePuma560();
  const BaseParameters base = pumaBase(model);
  Trajectory t = pumaTrajectory(model, 2.0, 0.0, 1);
  t.q.row(0).setZero();  // joint 1 never moves
  t.dq.row(0).setZero();
  t.ddq.row(0).setZero();
  try {
    estimateBaseParameters(base, observationFromTrajectory(model, t),
                           LeastSquaresMethod::kOrdinary);
    FAIL();
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("do not excite"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Iyy1R"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseLeastSquaresMethod("lasso"), InputError);
}

}  // namespace
}  // namespace dynid
