// Observation matrices: the regressor stacked over many samples, W theta = tau.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/trajectory.hpp"

namespace dynid {

/// Rows k n + j hold joint j of sample k: W (nN x p) and the measured torques tau (nN).
struct Observation {
  Eigen::MatrixXd W;
  Eigen::VectorXd tau;
  int num_samples = 0;
  int num_joints = 0;
  ParameterLayout layout;  // W's columns: the model's standard parameters
};

/// W and tau from a trajectory (q, dq, ddq, tau of every sample). Throws InputError when the
/// trajectory's joint count differs from the model's, or a value is not finite (naming the sample,
/// its time and the column, e.g. "sample 17 (t = 0.016 s): dq3 is not finite"), and before
/// allocating W when it and its factorisation would not fit in memory (core/memory.hpp).
Observation observationFromTrajectory(const Model& model, const Trajectory& trajectory);

/// Throws InputError when a value of sample k (0-based) is not finite, naming the sample (1-based),
/// its time and the column: "sample 17 (t = 0.016 s): dq3 is not finite".
void checkFiniteSample(const Trajectory& trajectory, int k);

/// checkFiniteSample for every sample: the first sample with a value that is not finite throws.
/// One vectorised pass over the columns when all are finite (the usual case).
void checkFiniteSamples(const Trajectory& trajectory);

/// The range random states draw joint i's position from: its limits, or +-pi rad (+-1 m for a
/// prismatic joint) when either is infinite. The structural analyses' one rule (this file's and
/// the floating robots', identifiability/floating/sensor_sets.hpp).
std::pair<double, double> randomStateRange(const Model& model, int i);

/// W from seeded random states for structural analysis: q uniform within the joint limits
/// (revolute joints without limits in [-pi, pi], prismatic in [-1, 1] m), dq uniform in
/// [-2, 2] rad/s, ddq uniform in [-5, 5] rad/s^2; tau = W theta of the model. Throws InputError
/// unless num_samples >= 1.
Observation observationFromRandomStates(const Model& model, int num_samples, std::uint64_t seed);

}  // namespace dynid
