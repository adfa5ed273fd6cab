// The physically consistent estimate on a floating robot's sensor set (docs/FLOATING.md,
// "Estimation"): the fixed-base estimator's problem (identifiability/physically_consistent.hpp:
// every body's pseudo-inertia positive definite, the non-negative drive terms kept positive, the
// entropic divergence from a prior) with the set's rows in standard coordinates, whitened by the
// channels' noise, as its data term. The base body is one more body of the problem; it has no
// drive terms (their columns are left out of the data, and the prior alone holds them).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/floating/floating_model.hpp"
#include "identifiability/floating/floating_fit.hpp"
#include "identifiability/physically_consistent.hpp"

namespace dynid {

struct FloatingPhysicalEstimate {
  /// The floating standard vector (the base body's 10, then the limbs'), every body's
  /// pseudo-inertia positive definite.
  Eigen::VectorXd theta;
  Eigen::VectorXd beta;  // the set's base parameters, P theta
  bool converged = false;
  std::string termination;  // solvePhysicalProblem's
  int iterations = 0;
  /// The problem it solved (the combined estimator's torque term): its layout has the base body
  /// as body 0 with drive-term entries the data never reach, held by the prior; `widened` is the
  /// solution there (theta with those entries), and `unexplained` half the whitened residual's
  /// squared norm no parameter can explain (R(p, p)^2 / 2 of floatingStandardFactor).
  std::shared_ptr<const PhysicalProblem> problem;
  Eigen::VectorXd widened;
  double unexplained = 0.0;
};

/// The floating standard vector's entries in a FloatingPhysicalEstimate's widened layout: widened
/// with `theta`'s values where the floating vector has them (the base body's drive entries left
/// as `widened` holds them).
Eigen::VectorXd widenFloating(const Eigen::VectorXd& theta, const Eigen::VectorXd& widened);
/// The floating standard vector of a widened one (the base body's drive entries dropped).
Eigen::VectorXd narrowFloating(const Eigen::VectorXd& widened, int num_parameters);

/// The estimate of `set` on `samples` weighted by `variances` (the feasible GLS's, so that torques,
/// forces and moments weigh by what they carry), `prior` a floating standard vector (the model's
/// own parameters; bodies outside the physical set are moved inside). Throws InputError on size
/// mismatches or a bad prior weight, NumericalError as makePhysicalProblem.
FloatingPhysicalEstimate fitFloatingPhysical(const FloatingModel& model, const BaseParameters& base,
                                             SensorSet set,
                                             const std::vector<FloatingMeasurement>& samples,
                                             const ChannelVariances& variances,
                                             const Eigen::VectorXd& prior,
                                             const PhysicalOptions& options = {});

}  // namespace dynid
