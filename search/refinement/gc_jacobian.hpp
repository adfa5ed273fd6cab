// The GC residuals' Jacobian with respect to the standard parameters, by automatic
// differentiation of the rollout (the refinement's Jet residuals, costs.cpp).
#pragma once

#include <Eigen/Core>

#include "core/model.hpp"
#include "search/gc_problem.hpp"

namespace dynid {

/// The Jacobian of every segment's 2n GC residuals (measured starts) with respect to the standard
/// parameters theta at `model` (rows: segment by segment; columns: theta's order), by automatic
/// differentiation (costs.cpp). Throws InputError on a joint-count mismatch, NumericalError when a
/// rollout diverges.
Eigen::MatrixXd gcJacobian(const Model& model, const GcProblem& problem, int num_threads = 1);

}  // namespace dynid
