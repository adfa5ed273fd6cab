// The weighted fit's intervals on floating datasets (analysis/floating/identify.hpp): with the
// noise of every channel unknown, `wls` estimates it and its intervals are calibrated, on the
// example quadruped and humanoid standing and on the quadruped in flight. Statistics over many
// simulated seeds: minutes under the sanitizers, where identify_test.cpp covers the same code.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "analysis/floating/identify.hpp"
#include "tests/common/floating_datasets.hpp"

namespace dynid {
namespace {

/// Over `seeds` noisy datasets: each set's z = (beta - truth) / sd RMS, the Mahalanobis distance
/// e^T Sigma^-1 e / p of its error e (1 when the whole covariance holds, in every direction), and
/// the estimated channel variances' mean ratio to the simulation's. In flight the marginal z share
/// one error (the whole robot's scale, which only the joint torques fix): their RMS spreads widely
/// from seed to seed (0.41 to 2.67; 0.945 over 30 seeds, measured with the CLI), and the base rows
/// hold exactly there while the fit gives them a small variance (near-constraints), so the
/// Mahalanobis distance is below 1 (those directions' errors are smaller than said): in flight
/// the check is the z RMS over more seeds.
void expectCalibrated(const test::FloatingExample& robot, int samples, int seeds,
                      const FloatingSimulationOptions& noise) {
  const FloatingModel model = test::loadExampleWithViscous(robot);
  std::map<SensorSet, double> sum, mahalanobis;
  std::map<SensorSet, int> count;
  double torque_ratio = 0.0, force_ratio = 0.0, moment_ratio = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    FloatingSimulationOptions options = noise;
    options.samples = samples;
    options.seed = static_cast<std::uint64_t>(seed);
    const FloatingIdentifyOutcome out = floatingIdentifyRun(
        model, FloatingIdentifyRequest{}, test::simulatedThroughFile(model, robot, options));
    for (const FloatingSetEstimate& s : out.sets) {
      ASSERT_TRUE(s.refused.empty()) << sensorSetName(s.base.set) << ": " << s.refused;
      sum[s.base.set] += s.model_z_rms * s.model_z_rms * static_cast<double>(s.fit.beta.size());
      count[s.base.set] += static_cast<int>(s.fit.beta.size());
      const Eigen::VectorXd e = s.fit.beta - s.model_beta;
      mahalanobis[s.base.set] +=
          e.dot(s.fit.covariance.ldlt().solve(e)) / static_cast<double>(e.size()) / seeds;
      if (s.base.set == SensorSet::kTorquesAndWrenches) {
        torque_ratio += s.variances.torque / (noise.torque_noise * noise.torque_noise) / seeds;
        force_ratio += s.variances.force / (noise.force_noise * noise.force_noise) / seeds;
        if (noise.moment_noise > 0.0)
          moment_ratio += s.variances.moment / (noise.moment_noise * noise.moment_noise) / seeds;
      }
    }
  }
  for (const auto& [set, total] : sum) {
    SCOPED_TRACE(sensorSetName(set));
    // chi^2_p / p averaged over the seeds: sd sqrt(2 / p / seeds), under 0.05 for p ~ 100 and 8
    // seeds; 0.15 is 3 sd.
    if (noise.motion != FloatingMotion::kFree) {
      EXPECT_NEAR(mahalanobis[set], 1.0, 0.15);
    }
    const double rms = std::sqrt(total / count[set]);
    // seeds x ~100 values: a standard normal sample's RMS that size is within 0.05 of 1 (3 sd);
    // in flight 32 seeds of correlated z (measured 1.04; the other cases 0.95-1.04).
    EXPECT_GT(rms, 0.9);
    EXPECT_LT(rms, 1.1);
  }
  // Thousands of residuals per seed: each variance within a few percent; 10 % is the bound.
  EXPECT_NEAR(torque_ratio, 1.0, 0.1);
  if (noise.motion != FloatingMotion::kFree) {  // in flight no force is measured
    EXPECT_NEAR(force_ratio, 1.0, 0.1);
  }
  if (noise.moment_noise > 0.0) {
    EXPECT_NEAR(moment_ratio, 1.0, 0.1);
  }
}

TEST(NoisyDataset, TheQuadrupedsWeightedIntervalsAreCalibratedWithTheNoiseUnknown) {
  FloatingSimulationOptions noise;
  noise.torque_noise = 0.5;  // N m: a current-sensing joint's level
  noise.force_noise = 2.0;   // N: a foot force sensor's
  expectCalibrated(test::kAnymalExample, 300, 8, noise);
}

/// In flight nothing holds: the base rows hold exactly (no channel feeds them) and are weighted as
/// near-constraints, the joint rows by the torques' estimated noise.
TEST(NoisyDataset, InFlightTheBaseRowsAreNearConstraints) {
  FloatingSimulationOptions noise;
  noise.motion = FloatingMotion::kFree;
  noise.torque_noise = 0.5;
  expectCalibrated(test::kAnymalExample, 150, 32, noise);
}

TEST(NoisyDataset, TheHumanoidsToo) {
  FloatingSimulationOptions noise;
  noise.torque_noise = 0.5;
  noise.force_noise = 5.0;   // N: a sole's six-axis sensor
  noise.moment_noise = 0.5;  // N m
  expectCalibrated(test::kRomeoExample, 150, 4, noise);
}

}  // namespace
}  // namespace dynid
