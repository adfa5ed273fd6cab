// Physically consistent identification: least squares on the torque residuals with every link's
// 10 inertial parameters in log-Cholesky form (core/log_cholesky.hpp), so every iterate is a
// realisable body, and the drive parameters Ia, Fv, Fc bounded below by 0 (Fo is free).
//
// The problem, for the observation W theta = tau with base parameters beta = P theta:
//     min over phi, d of  1/2 |(R P theta(phi, d) - c) / sigma|^2
//                       + 1/2 lambda (|phi - phi_prior|^2 + |(d - d_prior) / s_d|^2)
// where Q R = W1 (the base regressor; c = Q^T tau, so the first term equals the full residual up to
// a constant), sigma is the OLS residual standard deviation, floored at 1e-6 of the torques' RMS
// (so the first term is a chi-square), phi are the log-Cholesky coordinates of every link, d the
// drive parameters and s_d their prior magnitudes. phi_prior are those of the prior, each link
// moved inside the consistent set first. The prior term pulls the directions the data cannot see
// toward the prior; where the data do see, its pull is lambda against the chi-square's curvature,
// negligible for a small lambda. (A prior on the null-space component of theta alone would bias
// nothing, but it pulls inconsistent priors' links to the boundary of the consistent set, where
// log-Cholesky coordinates diverge and the solver stalls: tried and dropped.)
// Solved by Ceres (Levenberg-Marquardt, dense QR) from two starts, and the lower final cost kept:
// beta_OLS lifted to standard parameters with the prior's dependent ones, and the prior itself,
// each link first moved inside the consistent set by a margin (Ia, Fv, Fc clamped to >= 0).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/parameters.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/observation.hpp"

namespace ceres {
class CostFunction;
}

namespace dynid {

struct PhysicalOptions {
  /// lambda; 0 (default): no prior, the unseen directions stay near the start. With exact data a
  /// prior slows convergence: the chi-square then outweighs it by about 1e12.
  double prior_weight = 0.0;
  int max_iterations = 200;
  double function_tolerance = 1e-12;  // Ceres's relative cost-change tolerance
  int num_threads = 1;
  /// Called with the standard parameters of every iterate (tests check consistency there).
  std::function<void(const Eigen::VectorXd& theta)> on_iterate = {};
};

/// The prepared problem (see the header comment for the symbols).
struct PhysicalProblem {
  ParameterLayout layout;
  Eigen::MatrixXd R;             // num_base x num_base
  Eigen::VectorXd c;             // num_base
  double sigma = 1.0;            // [N m]
  Eigen::MatrixXd P;             // num_base x p
  Eigen::VectorXd prior_blocks;  // the prior's parameter blocks (phi_prior, d_prior), concatenated
  Eigen::VectorXd drive_scales;  // s_d, one per drive parameter
  double prior_weight = 0.0;

  /// Parameter blocks of the cost: per link its 10 log-Cholesky entries, then, with drives, per
  /// joint its 3 or 4 drive parameters.
  std::vector<int> blockSizes() const;
  int numResiduals() const;
};

/// Builds the problem. Throws InputError on size mismatches, NumericalError when the data do not
/// excite every base parameter.
PhysicalProblem makePhysicalProblem(const BaseParameters& base, const Observation& observation,
                                    const Eigen::VectorXd& prior, double prior_weight,
                                    double sigma);

/// The cost function of the problem (automatic differentiation; the caller owns it). Its residuals:
/// the data term's num_base, then (lambda > 0) the prior term's, one per parameter.
std::unique_ptr<ceres::CostFunction> makePhysicalCost(const PhysicalProblem& problem);

/// The standard parameter vector of the parameter blocks (blockSizes(), concatenated).
Eigen::VectorXd standardFromPhysicalBlocks(const ParameterLayout& layout,
                                           const Eigen::VectorXd& blocks);
/// The parameter blocks, concatenated, of a standard vector whose links all have positive definite
/// pseudo-inertias (throws NumericalError otherwise).
Eigen::VectorXd physicalBlocksFromStandard(const ParameterLayout& layout,
                                           const Eigen::VectorXd& theta);

struct PhysicalEstimate {
  Eigen::VectorXd theta;                // standard parameters, physically consistent
  Eigen::VectorXd beta;                 // P theta
  Eigen::VectorXd start_theta;          // the consistent start derived from OLS
  std::vector<int> inconsistent_links;  // links (0-based) whose OLS lift was not consistent
  BaseEstimate ols;                     // the OLS estimate it started from
  Eigen::MatrixXd covariance;           // of beta: sigma_pc^2 (W1^T W1)^-1 (constraints inactive)
  Eigen::VectorXd std_dev;
  Eigen::VectorXd residual_rms;       // per joint [N m]
  std::vector<std::string> at_bound;  // drive parameters held at their bound 0
  std::vector<double> cost_history;   // Ceres cost at every iteration (the first is the start)
  std::string termination;            // Ceres termination type and message
  bool usable = false;                // Ceres's IsSolutionUsable()
  int iterations = 0;
};

/// The physically consistent estimate. `prior` is a standard vector (p entries) whose links need
/// not be consistent; it supplies the dependent parameters of the start and the prior term.
/// Throws InputError on size mismatches, NumericalError as estimateBaseParameters.
PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const Observation& observation,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options = {});

}  // namespace dynid
