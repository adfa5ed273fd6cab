// Physically consistent identification: the least-squares fit of the torques over the standard
// parameters whose links all have a positive definite pseudo-inertia (core/log_cholesky.hpp),
// regularised by the entropic divergence from a prior, with the drive parameters the drive-term
// table marks non-negative kept positive; strictly convex, solved by Newton's method along the
// interior. The objective and the solver: docs/REFINEMENT.md, "The physically consistent problem".
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/parameters.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

/// The prior weight's one default and range (every front end's and request's).
inline constexpr double kDefaultPriorWeight = 1.0;
/// Throws InputError unless `weight` is finite and > 0 ("the prior weight must be finite and > 0").
void checkPriorWeight(double weight);

struct PhysicalOptions {
  /// lambda, > 0: the weight of the divergence from the prior, in chi-square units
  /// (docs/REFINEMENT.md). 1: the prior counts about like one more observation. Much smaller
  /// weights leave the unseen directions free to take implausible values that buy room from the
  /// boundary (on the Panda log 1e-3 gives link 2 a mass of 50 kg; 1 gives 2 kg) and take many more
  /// Newton steps.
  double prior_weight = kDefaultPriorWeight;
  int max_iterations = 1000;
  /// Newton decrement tolerance: stop when the quadratic model says F is within this of its
  /// minimum [chi-square units; 1/2 is one standard deviation].
  double tolerance = 1e-9;
  /// Called with the standard parameters of every iterate (tests check consistency there).
  std::function<void(const Eigen::VectorXd& theta)> on_iterate = {};
};

/// The prepared problem (the symbols: docs/REFINEMENT.md, "The physically consistent problem").
struct PhysicalProblem {
  ParameterLayout layout;
  Eigen::MatrixXd A;      // R P / sigma, num_base x p: the data term is |A theta - b|^2 / 2
  Eigen::VectorXd b;      // c / sigma
  double sigma = 1.0;     // [N m]
  Eigen::VectorXd prior;  // the prior, each link moved inside the physical set
  std::vector<Eigen::Matrix4d> prior_inverse;  // J_i,prior^-1
  std::vector<double> prior_log_det;           // log det J_i,prior
  Eigen::VectorXd scales;      // s_j per standard parameter (used for the drive terms)
  std::vector<char> positive;  // per standard parameter: a drive term bounded below by 0
  double prior_weight = kDefaultPriorWeight;

  /// F(theta), or +inf when theta is outside the physical set.
  double cost(const Eigen::VectorXd& theta) const;
  /// Gradient and Hessian of F at a theta inside the physical set.
  void derivatives(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient,
                   Eigen::MatrixXd* hessian) const;
};

/// Builds the problem from the data's augmented triangular factor [R c; 0 rho] of [W1 | tau]
/// ((b + 1) square, LeastSquaresStream::augmentedFactor): all the data term needs, whatever the
/// log's length. `layout` is the model's. Throws InputError on size mismatches, prior_weight <= 0
/// or sigma <= 0, NumericalError when the prior has a link with no positive definite
/// pseudo-inertia.
PhysicalProblem makePhysicalProblem(const BaseParameters& base, const ParameterLayout& layout,
                                    const Eigen::MatrixXd& augmented, const Eigen::VectorXd& prior,
                                    double prior_weight, double sigma);
/// The problem from a data term already in standard coordinates: |A theta - b|^2 / 2, A and b
/// whitened (sigma 1), e.g. one body's block when the rest of the robot is known
/// (identifiability/payload.hpp). Throws InputError on size mismatches or prior_weight <= 0,
/// NumericalError when the prior has a link with no positive definite pseudo-inertia.
PhysicalProblem makePhysicalProblem(const ParameterLayout& layout, Eigen::MatrixXd A,
                                    Eigen::VectorXd b, const Eigen::VectorXd& prior,
                                    double prior_weight);
/// The same from an observation (its rows streamed into a LeastSquaresStream).
PhysicalProblem makePhysicalProblem(const BaseParameters& base, const Observation& observation,
                                    const Eigen::VectorXd& prior, double prior_weight,
                                    double sigma);

struct PhysicalEstimate {
  Eigen::VectorXd theta;                // standard parameters, physically consistent
  Eigen::VectorXd beta;                 // P theta
  Eigen::VectorXd start_theta;          // the consistent start derived from OLS
  std::vector<int> inconsistent_links;  // links (0-based) whose OLS lift was not consistent
  BaseEstimate ols;                     // the OLS estimate it started from
  Eigen::MatrixXd covariance;           // of beta: sigma_pc^2 (W1^T W1)^-1 (constraints inactive)
  Eigen::VectorXd std_dev;
  Eigen::VectorXd residual_rms;       // per joint [N m]
  std::vector<std::string> at_bound;  // positive drive terms pressed to 0 (below 1e-6 of scale)
  std::vector<double> cost_history;   // F at every iteration (the first is the start)
  std::string termination;  // "CONVERGENCE: ..." or "NO_CONVERGENCE: ..." with the numbers
  bool usable = false;      // finite and physically consistent
  int iterations = 0;
  /// The problem it solved (the combined estimator adds the GC residuals to it), and its data
  /// term's constant: what no parameter explains, rho^2 / (2 sigma^2) [chi-square units], so that
  /// problem->cost + unexplained - (the prior term) is the whole data's chi-square / 2.
  std::shared_ptr<const PhysicalProblem> problem;
  double unexplained = 0.0;
};

/// A problem's minimiser from an interior start (every link's pseudo-inertia positive definite,
/// every positive drive term > 0): Newton's method along the barrier path, as the estimator runs
/// it.
struct PhysicalSolution {
  Eigen::VectorXd theta;
  bool converged = false;
  std::string termination;  // "CONVERGENCE: ..." or "NO_CONVERGENCE: ..."
  int iterations = 0;
  std::vector<double> cost_history;
};
/// Throws InputError when the start has the wrong size or is not inside the physical set.
PhysicalSolution solvePhysicalProblem(const PhysicalProblem& problem, Eigen::VectorXd start,
                                      const PhysicalOptions& options = {});

/// The physically consistent estimate from every sample in `stream` (of the model whose parameter
/// layout is `layout`): its OLS estimate, factor and per-joint residuals are all it takes, so the
/// memory does not grow with the log. `prior` is a standard vector (p entries) whose links need
/// not be consistent; it supplies the dependent parameters of the start and the prior term.
/// Throws InputError on size mismatches, NumericalError as LeastSquaresStream::estimate.
PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const ParameterLayout& layout,
                                              LeastSquaresStream& stream,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options = {});
/// The same from an observation: its rows streamed, sample by sample, into a LeastSquaresStream
/// over every base column (equal to a stream of the model's own trajectory to round-off).
PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const Observation& observation,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options = {});

}  // namespace dynid
