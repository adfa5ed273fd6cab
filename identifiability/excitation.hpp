// How well a motion determines the base parameters: the criteria of excitation design, from the
// base regressor W1 of the motion (the joint torque regressor's independent columns, stacked over
// the motion's samples; rows k n + j for joint j of sample k).
#pragma once

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"

namespace dynid {

struct MotionScore {
  int samples = 0;
  double condition_unit = 0.0;  // cond(W1 D^-1), D = diag of W1's column norms (scale-free)
  double condition = 0.0;       // cond(W1) in SI units (depends on the units of each parameter)
  double log_det = 0.0;         // log det(W1^T W1 / rows): D-optimality, per row
  /// Expected standard deviation of each base parameter (base order) by ordinary least squares
  /// with independent torque noise of standard deviation `torque_noise` on every joint:
  /// sigma sqrt(diag((W1^T W1)^-1)). Infinity where W1 is rank deficient.
  Eigen::VectorXd std_dev;
  /// 100 std_dev_j / s_j [%], s = baseParameterScale(beta) for the model's own base parameters
  /// beta (|beta_j|; the mean magnitude for a structurally zero beta_j).
  Eigen::VectorXd relative_std;
  /// RMS of std_dev_j / s_j: the expected RMS relative base-parameter error of ordinary least
  /// squares at this noise (what baseParameterError measures); infinity when rank deficient.
  double relative_rms = 0.0;
};

/// Scores the motion's q, dq, ddq (its tau is not used) for the model's base parameters `base`
/// (from structuralBaseParameters of the same model). Streams W1 through a TallQr: memory is
/// O(base^2), whatever the motion's length. Throws InputError when the motion's joint count
/// differs from the model's, it has no samples, a value is not finite, or torque_noise <= 0.
MotionScore scoreMotion(const Model& model, const BaseParameters& base, const Trajectory& motion,
                        double torque_noise);

}  // namespace dynid
