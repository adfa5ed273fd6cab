// Simulated floating datasets for the tests of analysis/floating/ (header-only: it needs the
// analysis floor, which the common test library does not link).
#pragma once

#include <cstdlib>
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

}  // namespace dynid::test
