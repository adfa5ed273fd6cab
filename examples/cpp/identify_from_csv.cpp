// Identify a robot's base parameters from a dataset CSV by least squares, step by step with the
// library: the structural base parameters (what the torques can determine), the observation
// matrix of the dataset, the estimate with its relative standard deviations, and its error
// against the truth. `dynid identify` runs the same steps (analysis/runs/runs.hpp, identifyRun).
//
//   example_identify_from_csv [DATASET.csv [ROBOT]]
// ROBOT is what `--robot` takes (puma560, panda, a .urdf or .json file; default puma560). Without
// a dataset it first simulates 4 s of the PUMA 560 with 0.05 N m of torque noise and writes them
// to a temporary CSV, which it then reads like any other dataset. A file it cannot use is reported
// (the library's errors name the file, the row and the field) with exit code 1, never an abort.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "analysis/runs/identify.hpp"
#include "analysis/runs/simulate.hpp"
#include "data/dataset_csv.hpp"
#include "data/robots.hpp"

namespace {

int run(int argc, char** argv) {
  using namespace dynid;
  const Model robot = loadRobot(argc > 2 ? argv[2] : "puma560");
  std::string csv;
  if (argc > 1) {
    csv = argv[1];
  } else {
    // A dataset as `dynid simulate --robot puma560 --duration 4 --noise-tau 0.05` writes it.
    SimulateRequest request;
    request.robot = robot;
    request.amplitude = Eigen::VectorXd::Constant(robot.numJoints(), 0.5);
    request.simulation.duration = 4.0;
    request.simulation.noise_tau = 0.05;
    csv = (std::filesystem::temp_directory_path() /
           ("dynid_example_" + std::to_string(::getpid()) + ".csv"))
              .string();
    writeDatasetCsv(csv, simulateRun(request).trajectory);
  }

  // What the torques can determine, from random states of the model: 36 base parameters for the
  // PUMA, each a combination of standard ones.
  const BaseParameters base = structuralBaseParameters(robot);
  // The dataset's observation W theta = tau, and the OLS estimate of beta.
  const Trajectory data = readDatasetCsv(csv, robot.numJoints());
  const Observation observation = observationFromTrajectory(robot, data);
  const BaseEstimate estimate =
      estimateBaseParameters(base, observation, LeastSquaresMethod::kOrdinary);
  if (argc <= 1) std::filesystem::remove(csv);

  const Eigen::VectorXd truth = base.project(robot.standardParameters());
  std::printf("%d samples, %d base parameters, condition number %.3g\n\n", data.numSamples(),
              base.numBase(), estimate.condition_number);
  std::printf("%-40s %12s %12s %9s\n", "base parameter", "estimate", "model", "%sigma");
  for (int j = 0; j < base.numBase(); ++j)
    std::printf("%-40s %12.5g %12.5g %9.3g\n", base.expression(j).substr(0, 40).c_str(),
                estimate.beta[j], truth[j], estimate.relative_std_dev_percent[j]);
  // Parameters with a large %sigma are barely excited by this motion: their estimates are noise.
  std::printf("\nresidual RMS per joint [N m]:");
  for (int j = 0; j < robot.numJoints(); ++j) std::printf(" %.4f", estimate.residual_rms[j]);
  std::printf("\n");
  // Simulated from the model with 0.05 N m of noise, the fit must explain the torques down to
  // that noise on every joint (10 %: the spread of an RMS over 4000 samples is about 1 %).
  bool at_noise = true;
  for (int j = 0; j < robot.numJoints(); ++j)
    at_noise = at_noise && std::abs(estimate.residual_rms[j] - 0.05) < 0.005;
  return argc > 1 || at_noise ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "example_identify_from_csv: error: %s\n", e.what());
    return 1;
  }
}
