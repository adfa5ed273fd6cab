// Uncertainty of a refined estimate, in base-parameter coordinates (refine.hpp says why): the
// information about beta with the segment starts eliminated, cov(beta) = sigma^2 H^-1, and the
// directions of the free parameters that leave beta unchanged.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/parallel.hpp"
#include "search/refinement/costs.hpp"
#include "search/refinement/options.hpp"

namespace dynid {

/// The information about beta left after eliminating the starts: with segment s's Jacobian blocks
/// jb[s] (beta), js[s] (its start; no columns when the starts are measured) and jn[s] (the next
/// segment's start, for chained starts; no columns otherwise), H_bb - H_bs H_ss^-1 H_sb of
/// H = J^T J for the stacked J, by a sparse LDL^T of H_ss (block tridiagonal). A matrix of NaN when
/// H_ss is singular; empty without segments.
Eigen::MatrixXd eliminateStarts(const std::vector<RowMajorMatrix>& jb,
                                const std::vector<RowMajorMatrix>& js,
                                const std::vector<RowMajorMatrix>& jn);

/// J^T J of the GC residuals with respect to beta at `beta` (`map` lifts beta to the model), the
/// starts eliminated by their Schur complement when estimated (a sparse LDL^T of the starts' block
/// tridiagonal J^T J, block diagonal when no segment ends on the next start); `squared_sum` gets
/// the sum of squared residuals (NaN when a rollout diverged).
Eigen::MatrixXd betaInformation(const Model& structure, const BetaLift& map,
                                const GcProblem& problem, const Eigen::VectorXd& beta,
                                Eigen::MatrixXd starts, const RefineOptions& options,
                                ThreadPool& pool, double& squared_sum);

/// Typical magnitude for scaling: |v_j|, or the mean magnitude of the non-zero entries for a 0
/// (an entry below 1e-9 of the mean magnitude counts as a round-off 0).
Eigen::VectorXd magnitudes(const Eigen::VectorXd& v);

/// d beta / d x = P d theta / d x at x, with beta scaled by its magnitudes and x by its own (or
/// half its range for a zero): singular values, numerical rank and right singular vectors.
struct FreeAnalysis {
  Eigen::VectorXd singular_values, x_scale;
  Eigen::MatrixXd v;  // k x k; columns rank.. span the free directions (in scaled x)
  int rank = 0;
};
FreeAnalysis analyseFreeDirections(const Model& structure, const ParameterSpace& space,
                                   const Eigen::MatrixXd& P, const Eigen::VectorXd& x);

/// Fills result.beta, beta_covariance, beta_std_dev, sigma2, degrees_of_freedom,
/// information_rank, beta_singular, free_parameter_rank and free_directions at result.x (and
/// result.initial_states).
void baseUncertainty(const Model& structure, const ParameterSpace& space, const GcProblem& problem,
                     const BaseCoordinates& base, const RefineOptions& options,
                     RefineResult& result, ThreadPool& pool);

}  // namespace dynid
