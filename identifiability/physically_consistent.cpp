#include "identifiability/physically_consistent.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/log_cholesky.hpp"

namespace dynid {

namespace {

/// Typical magnitude of each standard parameter's kind in theta (RMS over links of the non-zero
/// values; 1 when all are zero).
Eigen::VectorXd kindScales(const ParameterLayout& layout, const Eigen::VectorXd& theta) {
  const int per = layout.perLink();
  // Kinds: mass, first moments, inertias, then one per drive term.
  const auto kind = [&](int k) {
    return k == 0 ? 0 : k <= 3 ? 1 : k <= 9 ? 2 : 3 + layout.drives.termAt(k - kLinkParameterCount);
  };
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(3 + kDriveTermCount);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(3 + kDriveTermCount);
  for (int i = 0; i < layout.size(); ++i)
    if (theta[i] != 0.0) sum[kind(i % per)] += theta[i] * theta[i], count[kind(i % per)] += 1;
  Eigen::VectorXd out(layout.size());
  for (int i = 0; i < layout.size(); ++i) {
    const int k = kind(i % per);
    out[i] = count[k] > 0 ? std::sqrt(sum[k] / count[k]) : 1.0;
  }
  return out;
}

/// The pseudo-inertia's derivative with respect to each of the 10 standard parameters (J is
/// linear in them).
const std::array<Eigen::Matrix4d, 10>& pseudoInertiaBasis() {
  static const std::array<Eigen::Matrix4d, 10> basis = [] {
    std::array<Eigen::Matrix4d, 10> out;
    for (int k = 0; k < 10; ++k) out[k] = pseudoInertia(Eigen::Matrix<double, 10, 1>::Unit(k));
    return out;
  }();
  return basis;
}

/// log det of a positive definite J, or NaN when J is not positive definite.
double logDet(const Eigen::Matrix4d& j, Eigen::Matrix4d* inverse = nullptr) {
  const Eigen::LLT<Eigen::Matrix4d> llt(j);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector4d diagonal = llt.matrixLLT().diagonal();
  if (!(diagonal.array() > 0.0).all()) return std::numeric_limits<double>::quiet_NaN();
  if (inverse != nullptr) *inverse = llt.solve(Eigen::Matrix4d::Identity());
  return 2.0 * diagonal.array().log().sum();
}

/// The observation's rows, sample by sample, in a stream over every base column.
LeastSquaresStream streamOf(const BaseParameters& base, const Observation& observation) {
  if (observation.layout.size() != base.numStandard() ||
      observation.layout.num_links != observation.num_joints)
    throw InputError("the base parameters do not match the observation's joint count");
  if (static_cast<long long>(observation.num_samples) * observation.num_joints < base.numBase())
    throw InputError("fewer torque rows than base parameters");
  LeastSquaresStream stream(base, observation.num_joints);
  const int n = observation.num_joints;
  for (int k = 0; k < observation.num_samples; ++k)
    stream.add(observation.W.middleRows(static_cast<Eigen::Index>(k) * n, n),
               observation.tau.segment(static_cast<Eigen::Index>(k) * n, n));
  return stream;
}
}  // namespace

PhysicalProblem makePhysicalProblem(const BaseParameters& base, const Observation& observation,
                                    const Eigen::VectorXd& prior, double prior_weight,
                                    double sigma) {
  LeastSquaresStream stream = streamOf(base, observation);
  return makePhysicalProblem(base, observation.layout, stream.augmentedFactor(), prior,
                             prior_weight, sigma);
}

void checkPriorWeight(double weight) {
  if (!(weight > 0.0) || !std::isfinite(weight))
    throw InputError("the prior weight must be finite and > 0");
}

PhysicalProblem makePhysicalProblem(const BaseParameters& base, const ParameterLayout& layout,
                                    const Eigen::MatrixXd& augmented, const Eigen::VectorXd& prior,
                                    double prior_weight, double sigma) {
  if (prior.size() != base.numStandard())
    throw InputError("the prior has " + std::to_string(prior.size()) + " parameters, expected " +
                     std::to_string(base.numStandard()));
  checkPriorWeight(prior_weight);
  if (!(sigma > 0.0)) throw InputError("sigma must be positive");
  const int p = base.numStandard(), b = base.numBase();
  if (layout.size() != p)
    throw InputError("the parameter layout has " + std::to_string(layout.size()) +
                     " parameters, the base parameters are of " + std::to_string(p));
  if (augmented.rows() != b + 1 || augmented.cols() != b + 1)
    throw InputError("the data's factor is " + std::to_string(augmented.rows()) + " x " +
                     std::to_string(augmented.cols()) + ", expected " + std::to_string(b + 1) +
                     " square");
  // [R c; 0 rho] of [W1 | tau]: the data term is |R P theta - c|^2 / sigma^2 up to a constant.
  const Eigen::MatrixXd R = augmented.topLeftCorner(b, b).triangularView<Eigen::Upper>();
  PhysicalProblem problem =
      makePhysicalProblem(layout, R * base.projectionMatrix() / sigma,
                          augmented.col(b).head(b) / sigma, prior, prior_weight);
  problem.sigma = sigma;
  return problem;
}

PhysicalProblem makePhysicalProblem(const ParameterLayout& layout, Eigen::MatrixXd A,
                                    Eigen::VectorXd b, const Eigen::VectorXd& prior,
                                    double prior_weight) {
  checkPriorWeight(prior_weight);
  const int p = layout.size();
  if (prior.size() != p || A.cols() != p || A.rows() != b.size())
    throw InputError("the data term is " + std::to_string(A.rows()) + " x " +
                     std::to_string(A.cols()) + " with " + std::to_string(b.size()) +
                     " targets and the prior has " + std::to_string(prior.size()) +
                     " parameters, for a layout of " + std::to_string(p));
  PhysicalProblem problem;
  problem.layout = layout;
  problem.A = std::move(A);
  problem.b = std::move(b);
  problem.prior_weight = prior_weight;
  // The prior: each link moved well inside the physical set; its pseudo-inertia's inverse.
  const int per = layout.perLink();
  problem.prior = prior;
  for (int i = 0; i < layout.num_links; ++i) {
    problem.prior.segment<10>(i * per) = nearestConsistent(prior.segment<10>(i * per).eval(), 1e-2);
    Eigen::Matrix4d inverse;
    const double log_det = logDet(pseudoInertia(problem.prior.segment<10>(i * per)), &inverse);
    if (!std::isfinite(log_det))
      throw NumericalError("the prior's link " + std::to_string(i + 1) +
                           " has no positive definite pseudo-inertia");
    problem.prior_inverse.push_back(inverse);
    problem.prior_log_det.push_back(log_det);
  }
  // Drive terms: the table's non-negative ones (Ia, Fv, Fc, Fs) and their scales.
  const Eigen::VectorXd kinds = kindScales(layout, prior);
  problem.scales = kinds;
  problem.positive.assign(p, 0);
  for (int i = 0; i < layout.num_links; ++i)
    for (int k = 0; k < per - kLinkParameterCount; ++k) {
      const int index = i * per + kLinkParameterCount + k;
      problem.positive[index] = kDriveTermTable[layout.drives.termAt(k)].non_negative ? 1 : 0;
      if (problem.positive[index] && prior[index] > 0.0) problem.scales[index] = prior[index];
    }
  return problem;
}

double PhysicalProblem::cost(const Eigen::VectorXd& theta) const {
  double out = 0.5 * (A * theta - b).squaredNorm();
  const int per = layout.perLink();
  for (int i = 0; i < layout.num_links; ++i) {
    const Eigen::Matrix4d j = pseudoInertia(theta.segment<10>(i * per));
    const double log_det = logDet(j);
    if (!std::isfinite(log_det)) return std::numeric_limits<double>::infinity();
    out += prior_weight * ((prior_inverse[i] * j).trace() - log_det + prior_log_det[i] - 4.0);
    for (int k = i * per + kLinkParameterCount; k < (i + 1) * per; ++k) {
      const double x = theta[k] / scales[k];
      if (positive[k]) {
        if (!(x > 0.0)) return std::numeric_limits<double>::infinity();
        out += prior_weight * (x - std::log(x) - 1.0);
      } else {
        const double d = (theta[k] - prior[k]) / scales[k];
        out += prior_weight * 0.5 * d * d;
      }
    }
  }
  return out;
}

void PhysicalProblem::derivatives(const Eigen::VectorXd& theta, Eigen::VectorXd* gradient,
                                  Eigen::MatrixXd* hessian) const {
  *gradient = A.transpose() * (A * theta - b);
  *hessian = A.transpose() * A;
  const std::array<Eigen::Matrix4d, 10>& basis = pseudoInertiaBasis();
  const int per = layout.perLink();
  for (int i = 0; i < layout.num_links; ++i) {
    Eigen::Matrix4d inverse;
    logDet(pseudoInertia(theta.segment<10>(i * per)), &inverse);
    // d/dtheta_k [tr(Jp^-1 J) - log det J] = tr(Jp^-1 E_k) - tr(J^-1 E_k);
    // d2/dtheta_k dtheta_l = tr(J^-1 E_k J^-1 E_l).
    std::array<Eigen::Matrix4d, 10> products;
    for (int k = 0; k < 10; ++k) {
      products[k] = inverse * basis[k];
      (*gradient)[i * per + k] +=
          prior_weight * ((prior_inverse[i] * basis[k]).trace() - products[k].trace());
    }
    for (int k = 0; k < 10; ++k)
      for (int l = 0; l < 10; ++l)
        (*hessian)(i * per + k, i * per + l) += prior_weight * (products[k] * products[l]).trace();
    for (int k = i * per + kLinkParameterCount; k < (i + 1) * per; ++k) {
      const double s = scales[k];
      if (positive[k]) {
        (*gradient)[k] += prior_weight * (1.0 / s - 1.0 / theta[k]);
        (*hessian)(k, k) += prior_weight / (theta[k] * theta[k]);
      } else {
        (*gradient)[k] += prior_weight * (theta[k] - prior[k]) / (s * s);
        (*hessian)(k, k) += prior_weight / (s * s);
      }
    }
  }
}

PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const Observation& observation,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options) {
  LeastSquaresStream stream = streamOf(base, observation);
  return estimatePhysicallyConsistent(base, observation.layout, stream, prior, options);
}

namespace {

/// The start: OLS lifted with the prior's dependent parameters, each link that is not inside the
/// physical set moved just inside (1e-8 of the normalised pseudo-inertia), and the positive drive
/// terms raised to at least 1e-2 of their scale. F is strictly convex: any interior start reaches
/// the one minimum.
Eigen::VectorXd consistentStart(const BaseParameters& base, const ParameterLayout& layout,
                                const PhysicalProblem& problem, const Eigen::VectorXd& ols_beta,
                                const Eigen::VectorXd& prior,
                                std::vector<int>& inconsistent_links) {
  const int per = layout.perLink(), p = layout.size();
  Eigen::VectorXd theta = base.standardFromBase(ols_beta, prior);
  for (int i = 0; i < layout.num_links; ++i) {
    const Eigen::Matrix<double, 10, 1> link = theta.segment<10>(i * per);
    const Eigen::Matrix<double, 10, 1> fixed = nearestConsistent(link, 1e-8);
    if (fixed != link) inconsistent_links.push_back(i);
    theta.segment<10>(i * per) = fixed;
  }
  for (int k = 0; k < p; ++k)
    if (problem.positive[k]) theta[k] = std::max(theta[k], 1e-2 * problem.scales[k]);
  return theta;
}

/// The outcome of the barrier path: converged, why it stopped, the Newton iterations taken.
struct PathOutcome {
  bool converged = false;
  std::string why;
  int iterations = 0;
};

/// Damped Newton along the barrier path: lambda starts at the data term's size at the start (the
/// divergence then weighs as much as the misfit, the minimiser is well inside the physical set
/// and Newton converges in a few steps) and falls tenfold per stage to the requested value, each
/// stage starting from the last one's minimiser (the interior-point method's central path). Each
/// step solves the Jacobi-scaled Newton system (the Hessian mixes the data's curvature, up to
/// 1/sigma^2, with the barrier's); backtracking (Armijo, halving) keeps every iterate inside.
/// theta: the interior start in, the minimiser out; F after every step appended to cost_history.
PathOutcome barrierPath(const PhysicalProblem& problem, const PhysicalOptions& options,
                        Eigen::VectorXd& theta, std::vector<double>& cost_history) {
  const int p = static_cast<int>(theta.size());
  PhysicalProblem stage = problem;
  int stages = 0;
  const double misfit = 0.5 * (problem.A * theta - problem.b).squaredNorm();
  while (stage.prior_weight < misfit && stages < 30) stage.prior_weight *= 10.0, ++stages;
  double cost = stage.cost(theta);
  cost_history.push_back(problem.cost(theta));
  bool converged = false;
  std::string why;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    stage.derivatives(theta, &gradient, &hessian);
    const Eigen::VectorXd scale = hessian.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    Eigen::MatrixXd scaled = scale.asDiagonal() * hessian * scale.asDiagonal();
    Eigen::LLT<Eigen::MatrixXd> llt(scaled);
    for (double damping = 1e-14; llt.info() != Eigen::Success && damping < 1.0; damping *= 100.0)
      llt.compute(scaled + damping * Eigen::MatrixXd::Identity(p, p));
    const Eigen::VectorXd step = scale.asDiagonal() * llt.solve(-(scale.asDiagonal() * gradient));
    const double decrement = -gradient.dot(step);  // lambda^2; F - min of the quadratic model = /2
    if (!std::isfinite(decrement) || llt.info() != Eigen::Success) {
      why = "the Newton system could not be solved";
      break;
    }
    const bool last_stage = stage.prior_weight == problem.prior_weight;
    // F sums terms as large as F itself, so it resolves changes of a few ulps of |F| at best
    // (1e-14 |F| is ~45 ulps): a predicted decrease below that is as converged as the arithmetic
    // can tell, and asking for more only takes steps that change F by nothing.
    const double resolution = 1e-14 * std::abs(cost);
    const auto next_stage = [&] {
      stage.prior_weight = stages == 1 ? problem.prior_weight : stage.prior_weight / 10.0;
      --stages;
      cost = stage.cost(theta);
    };
    if (decrement / 2.0 <= std::max(last_stage ? options.tolerance : 1e-3, resolution)) {
      if (!last_stage) {  // the next stage of the path
        next_stage();
        continue;
      }
      converged = true;
      why = "Newton decrement / 2 = " + formatNumber(decrement / 2.0, 3) +
            " <= " + formatNumber(std::max(options.tolerance, resolution), 3) +
            (resolution > options.tolerance ? " (the resolution of F)" : "");
      break;
    }
    double t = 1.0, trial = stage.cost(theta + step);
    // Strictly lower as well: near F's resolution the Armijo bound rounds to F itself, and a step
    // that leaves F unchanged is no progress.
    while (!(trial <= cost - 0.25 * t * decrement && trial < cost) && t > 1e-12) {
      t *= 0.5;
      trial = stage.cost(theta + t * step);
    }
    if (t <= 1e-12) {
      // A stage's minimiser is only a waypoint of the path: where rounding stops its Newton steps
      // (exact data: a huge F whose Newton system is solved only roughly), go on to the next.
      if (!last_stage) {
        next_stage();
        continue;
      }
      why =
          "no decrease along the Newton step (decrement / 2 = " + formatNumber(decrement / 2.0, 3) +
          ", F = " + formatNumber(cost, 3) + ")";
      break;
    }
    theta += t * step;
    cost = trial;
    cost_history.push_back(problem.cost(theta));
    if (options.on_iterate) options.on_iterate(theta);
  }
  return {converged, why, iteration};
}

}  // namespace

PhysicalSolution solvePhysicalProblem(const PhysicalProblem& problem, Eigen::VectorXd start,
                                      const PhysicalOptions& options) {
  if (start.size() != problem.layout.size())
    throw InputError("the start has " + std::to_string(start.size()) + " parameters, expected " +
                     std::to_string(problem.layout.size()));
  if (!std::isfinite(problem.cost(start)))
    throw InputError("the start is not inside the physical set");
  PhysicalSolution out;
  out.theta = std::move(start);
  const PathOutcome path = barrierPath(problem, options, out.theta, out.cost_history);
  out.converged = path.converged;
  out.iterations = path.iterations;
  out.termination = std::string(path.converged ? "CONVERGENCE: " : "NO_CONVERGENCE: ") +
                    (path.why.empty() ? "Maximum number of iterations reached (" +
                                            std::to_string(options.max_iterations) + ")"
                                      : path.why);
  return out;
}

PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const ParameterLayout& layout,
                                              LeastSquaresStream& stream,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options) {
  if (layout.num_links != stream.numJoints())
    throw InputError("the parameter layout has " + std::to_string(layout.num_links) +
                     " links, the data " + std::to_string(stream.numJoints()) + " joints");
  PhysicalEstimate out;
  out.ols = stream.estimate(LeastSquaresMethod::kOrdinary);
  const Eigen::MatrixXd augmented = stream.augmentedFactor();
  const int b = base.numBase();
  const Eigen::VectorXd fitted = stream.fittedRows();  // rows at rest left out (FitRows)
  const double rows = fitted.sum();
  // sigma from the OLS residuals (|rho|, the factor's last entry), floored at 1e-6 of the torques'
  // RMS (|tau|: the factor's last column): with exact (noise-free) data the prior term must keep a
  // weight that holds the directions the data cannot see.
  const double tau_rms = augmented.col(b).norm() / std::sqrt(std::max(rows, 1.0));
  const double sigma_ols = std::max(std::abs(augmented(b, b)) / std::sqrt(std::max(rows - b, 1.0)),
                                    1e-6 * tau_rms + 1e-300);
  auto shared = std::make_shared<const PhysicalProblem>(
      makePhysicalProblem(base, layout, augmented, prior, options.prior_weight, sigma_ols));
  const PhysicalProblem& problem = *shared;
  out.problem = shared;
  out.unexplained = 0.5 * augmented(b, b) * augmented(b, b) / (sigma_ols * sigma_ols);
  const int p = layout.size();

  out.start_theta =
      consistentStart(base, layout, problem, out.ols.beta, prior, out.inconsistent_links);
  Eigen::VectorXd theta = out.start_theta;
  PathOutcome path = barrierPath(problem, options, theta, out.cost_history);
  if (!path.converged && path.why.empty())
    path.why =
        "Maximum number of iterations reached (" + std::to_string(options.max_iterations) + ")";
  out.termination = std::string(path.converged ? "CONVERGENCE: " : "NO_CONVERGENCE: ") + path.why;
  out.iterations = path.iterations;
  out.theta = theta;
  out.beta = base.project(out.theta);
  out.usable = std::isfinite(problem.cost(theta));
  const std::vector<std::string> names = standardParameterNames(layout);
  for (int k = 0; k < p; ++k)
    if (problem.positive[k] && out.theta[k] <= 1e-6 * problem.scales[k])
      out.at_bound.push_back(names[k]);

  // Residuals and the base covariance sigma^2 (R^T R)^-1 at the estimate.
  const Eigen::VectorXd squares = stream.residualSquares(out.beta);
  out.residual_rms = squares.cwiseQuotient(fitted.cwiseMax(1.0)).cwiseSqrt();
  const double sigma2 = squares.sum() / std::max(rows - b, 1.0);
  const Eigen::MatrixXd R = augmented.topLeftCorner(b, b).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_inv =
      R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
  out.covariance = sigma2 * r_inv * r_inv.transpose();
  out.std_dev = out.covariance.diagonal().cwiseSqrt();
  return out;
}

}  // namespace dynid
