// A payload on a floating robot (analysis/floating/payload.hpp): a 2 kg box on ANYmal's base and
// a 0.5 kg tool on a leg, simulated on the loaded robot and estimated with the unloaded model,
// from every sensor set: exact from noise-free data, within its intervals with noise.
#include "analysis/floating/payload.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "tests/common/floating_datasets.hpp"
#include "tests/common/text.hpp"

namespace dynid {
namespace {

/// A box of `mass` [kg], half-sizes 0.1 x 0.08 x 0.05 m, centred at `centre` in the link's frame:
/// its ten parameters about the link's origin.
Eigen::Matrix<double, 10, 1> box(double mass, const Eigen::Vector3d& centre) {
  RigidInertia<double> b;
  b.mass = mass;
  b.first_moment = mass * centre;
  const Eigen::Vector3d s(0.2, 0.16, 0.1);  // full sizes
  b.inertia.diagonal() << mass / 12 * (s[1] * s[1] + s[2] * s[2]),
      mass / 12 * (s[0] * s[0] + s[2] * s[2]), mass / 12 * (s[0] * s[0] + s[1] * s[1]);
  // Shifted to the link's origin (parallel axes): + m (|c|^2 1 - c c^T).
  b.inertia +=
      mass * (centre.squaredNorm() * Eigen::Matrix3d::Identity() - centre * centre.transpose());
  return toStandardVector(b);
}

/// ANYmal with the payload's parameters added to `link`'s body.
FloatingModel loaded(const FloatingModel& model, const std::string& link,
                     const Eigen::Matrix<double, 10, 1>& phi) {
  FloatingModel out = model;
  Eigen::VectorXd theta = out.standardParameters();
  const int body = model.findFrame(link)->body;
  const int first =
      body < 0 ? 0 : FloatingModel::limbColumn(model.limbs().parameterLayout().linkIndex(body, 0));
  theta.segment<10>(first) += phi;
  out.setStandardParameters(theta);
  return out;
}

struct Case {
  const char* link;
  double mass;
  Eigen::Vector3d centre;
};

class PayloadOnAnymal : public ::testing::TestWithParam<int> {};

TEST_P(PayloadOnAnymal, NoiseFreeEverySetRecoversIt) {
  const Case c = GetParam() == 0 ? Case{"base", 2.0, {0.1, 0.0, 0.15}}
                                 : Case{"RF_SHANK", 0.5, {0.05, -0.02, -0.1}};
  const FloatingModel model = test::loadExampleWithViscous(test::kAnymalExample);
  const Eigen::Matrix<double, 10, 1> phi = box(c.mass, c.centre);
  FloatingSimulationOptions options;
  options.samples = 150;
  const FloatingDataset data =
      test::simulatedThroughFile(loaded(model, c.link, phi), test::kAnymalExample, options);
  FloatingIdentifyRequest request;
  request.method = FloatingMethod::kOls;
  const FloatingIdentifyOutcome estimate = floatingIdentifyRun(model, request, data);
  const std::vector<FloatingPayload> payloads = floatingPayloads(model, estimate, data, c.link);
  ASSERT_EQ(payloads.size(), 3u);
  for (std::size_t k = 0; k < payloads.size(); ++k) {
    SCOPED_TRACE(std::string(c.link) + " " + sensorSetName(estimate.sets[k].base.set));
    ASSERT_TRUE(payloads[k].refused.empty()) << payloads[k].refused;
    // 1e-9 relative, the noise-free bound.
    EXPECT_LT((payloads[k].phi - phi).norm() / phi.norm(), 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Links, PayloadOnAnymal, ::testing::Values(0, 1));

TEST(FloatingPayload, WithNoiseItLiesWithinItsIntervals) {
  const FloatingModel model = test::loadExampleWithViscous(test::kAnymalExample);
  const Eigen::Matrix<double, 10, 1> phi = box(2.0, {0.1, 0.0, 0.15});
  FloatingSimulationOptions options;
  options.samples = 300;
  options.seed = 4;
  options.torque_noise = 0.5;
  options.force_noise = 2.0;
  const FloatingDataset data =
      test::simulatedThroughFile(loaded(model, "base", phi), test::kAnymalExample, options);
  const FloatingIdentifyOutcome estimate =
      floatingIdentifyRun(model, FloatingIdentifyRequest{}, data);
  for (const FloatingPayload& p : floatingPayloads(model, estimate, data, "base")) {
    ASSERT_TRUE(p.refused.empty()) << p.refused;
    const Eigen::Matrix<double, 10, 1> z =
        (p.phi - phi).cwiseQuotient(p.covariance.diagonal().cwiseSqrt());
    // |z| > 4 has probability 6e-5 per parameter for a calibrated interval.
    EXPECT_LT(z.cwiseAbs().maxCoeff(), 4.0) << z.transpose();
    // 2 kg from 300 states at 2 N a force component: a few tens of grams.
    EXPECT_LT(std::sqrt(p.covariance(0, 0)), 0.05);
  }
}

TEST(FloatingPayload, ALinkTheModelLacksIsNamed) {
  const FloatingModel model = test::loadExampleWithViscous(test::kAnymalExample);
  FloatingSimulationOptions options;
  options.samples = 20;
  const FloatingDataset data = test::simulatedThroughFile(model, test::kAnymalExample, options);
  const FloatingIdentifyOutcome estimate =
      floatingIdentifyRun(model, FloatingIdentifyRequest{}, data);
  try {
    floatingPayloads(model, estimate, data, "backpack");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_TRUE(test::contains(e.what(), "`payload_link`: 'backpack'")) << e.what();
  }
}

}  // namespace
}  // namespace dynid
