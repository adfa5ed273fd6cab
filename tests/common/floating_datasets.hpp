// Simulated floating datasets for the tests of analysis/floating/ (header-only: it needs the
// analysis floor, which the common test library does not link).
#pragma once

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/simulate.hpp"
#include "tests/common/floating_models.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::test {

/// The example with viscous friction (zero in the file: a column the data must find zero).
inline FloatingModel loadExampleWithViscous(const FloatingExample& robot) {
  FloatingModel model = loadExample(robot);
  model.setDriveTerms(DriveTerms::of({DriveTerm::kViscous}));
  return model;
}

/// A design of five harmonics for `model`'s joints over `period` [s], zero offset, every
/// coefficient uniform in +-`amplitude` (std::rand seeded with `seed`, a then b).
inline FourierSeries randomDesign(const FloatingModel& model, double period, double amplitude,
                                  unsigned seed) {
  FourierSeries design;
  design.period = period;
  const int n = model.numJoints();
  design.offset = Eigen::VectorXd::Zero(n);
  std::srand(seed);
  design.a = amplitude * Eigen::MatrixXd::Random(n, 5);
  design.b = amplitude * Eigen::MatrixXd::Random(n, 5);
  return design;
}

/// A simulated dataset of the example on its contacts (none in flight), through its file: written
/// and read back, as a user has it.
inline FloatingDataset simulatedThroughFile(const FloatingModel& model,
                                            const FloatingExample& robot,
                                            FloatingSimulationOptions options) {
  if (options.motion != FloatingMotion::kFree) options.contacts = contactsOf(model, robot.contacts);
  const std::string path = tempPath("floating_dataset.csv");
  writeFloatingDataset(path, simulateFloatingDataset(model, options));
  return readFloatingDataset(path, model);
}

/// The suspended ANYmal C's joints following a 2 s design of five harmonics, sampled at 1 kHz,
/// the torques and the support's wrench from `robot`'s inverse dynamics, noise-free.
inline FloatingDataset designed(const FloatingModel& robot) {
  FloatingSimulationOptions options;
  options.samples = 2000;
  options.motion = FloatingMotion::kSuspended;
  options.trajectory = randomDesign(robot, 2.0, 0.1, 5);
  return simulateFloatingDataset(robot, options);
}

/// The model with every link's mass and inertia 10 % more (a maker's model off by that much).
inline FloatingModel heavier(const FloatingModel& model) {
  FloatingModel out = model;
  Eigen::VectorXd theta = out.standardParameters();
  theta *= 1.1;  // mass, first moments and inertia scale alike: the centres of mass unchanged
  out.setStandardParameters(theta);
  return out;
}

/// `robot` suspended in two orientations, upright and tilted by 0.4 rad, the design's motion in
/// each (the second after a 1 s gap): a stand tilted between two recordings, joined; `noise` on
/// the joint torques [N m], the support's forces [N] (times 4) and moments [N m].
inline FloatingDataset twoTilts(const FloatingModel& robot, double noise = 0.0) {
  const FloatingDataset upright = designed(robot);
  const Eigen::Index N = upright.numSamples();
  auto joined = std::make_shared<FloatingDataset>(upright);
  const auto twice = [N](auto& m) {
    auto copy = m;
    m.resize(m.rows(), 2 * N);
    m << copy, copy;
  };
  twice(joined->orientation), twice(joined->twist), twice(joined->acceleration);
  twice(joined->q), twice(joined->dq), twice(joined->ddq);
  joined->time.resize(2 * N);
  joined->time << upright.time, upright.time.array() + upright.time[N - 1] + 1.0;
  const Eigen::Vector4d tilt(std::cos(0.2), std::sin(0.2), 0.0, 0.0);  // 0.4 rad about x
  joined->orientation.rightCols(N).colwise() = tilt;
  joined->tau.resize(0, 2 * N);
  joined->wrenches.clear();
  FloatingSimulationOptions options;
  options.motion = FloatingMotion::kSuspended;
  options.samples = static_cast<int>(2 * N);
  options.motion_from = joined;
  options.torque_noise = options.moment_noise = noise;
  options.force_noise = 4.0 * noise;
  return simulateFloatingDataset(robot, options);
}

}  // namespace dynid::test
