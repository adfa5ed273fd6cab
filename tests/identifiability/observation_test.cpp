#include "identifiability/observation.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "core/errors.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

Trajectory shortTrajectory(const Model& model) {
  return test::pumaSinusoidTrajectory(model, 0.2, 0.5, 0.3, 0.8);
}

TEST(Observation, StacksSamplesJointMajor) {
  const Model model = makePuma560(true);
  const Trajectory t = shortTrajectory(model);
  const Observation o = observationFromTrajectory(model, t);
  EXPECT_EQ(o.num_samples, t.numSamples());
  EXPECT_EQ(o.W.rows(), 6 * t.numSamples());
  EXPECT_EQ(o.W.cols(), 84);
  EXPECT_EQ(o.tau.segment(6 * 7, 6), t.tau.col(7));
  // Noise-free simulation: W theta reproduces the recorded torques (round-off of N m torques).
  EXPECT_LT((o.W * model.standardParameters() - o.tau).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Observation, NamesTheNonFiniteSample) {
  const Model model = makePuma560();
  Trajectory t = shortTrajectory(model);
  t.dq(2, 16) = std::nan("");
  try {
    observationFromTrajectory(model, t);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 17 (t = 0.016 s): dq3 is not finite"),
              std::string::npos)
        << e.what();
  }
  t.q.conservativeResize(5, Eigen::NoChange);
  EXPECT_THROW(observationFromTrajectory(model, t), InputError);
}

TEST(Observation, EverySampleIsCheckedAndTheFirstBadOneNamed) {
  const Model model = makePuma560();
  Trajectory t = shortTrajectory(model);
  EXPECT_NO_THROW(checkFiniteSamples(t));
  const auto message = [&] {
    try {
      checkFiniteSamples(t);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Each block of columns, and an infinity as well as a NaN.
  t.tau(0, 40) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(), "sample 41 (t = 0.04 s): tau1 is not finite");
  t.ddq(5, 30) = std::nan("");
  EXPECT_EQ(message(), "sample 31 (t = 0.03 s): ddq6 is not finite");
  t.q(1, 30) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(), "sample 31 (t = 0.03 s): q2 is not finite");
  t.dq(2, 16) = std::nan("");
  EXPECT_EQ(message(), "sample 17 (t = 0.016 s): dq3 is not finite");
}

TEST(Observation, RandomStatesAreSeededAndWithinLimits) {
  const Model model = makePuma560();
  const Observation a = observationFromRandomStates(model, 20, 3),
                    b = observationFromRandomStates(model, 20, 3),
                    c = observationFromRandomStates(model, 20, 4);
  EXPECT_EQ(a.W, b.W);
  EXPECT_NE(a.W, c.W);
  EXPECT_LT((a.W * model.standardParameters() - a.tau).norm(), 1e-12 * (1 + a.tau.norm()));
  EXPECT_THROW(observationFromRandomStates(model, 0, 1), InputError);
}

}  // namespace
}  // namespace dynid
