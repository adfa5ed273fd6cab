#include "identifiability/floating/floating_physical.hpp"

#include <algorithm>
#include <memory>

#include "core/errors.hpp"

namespace dynid {

Eigen::VectorXd widenFloating(const Eigen::VectorXd& theta, const Eigen::VectorXd& widened) {
  Eigen::VectorXd out = widened;
  const Eigen::Index rest = theta.size() - kLinkParameterCount;
  out.head<kLinkParameterCount>() = theta.head<kLinkParameterCount>();
  out.tail(rest) = theta.tail(rest);
  return out;
}

Eigen::VectorXd narrowFloating(const Eigen::VectorXd& widened, int num_parameters) {
  Eigen::VectorXd out(num_parameters);
  const Eigen::Index rest = num_parameters - kLinkParameterCount;
  out.head<kLinkParameterCount>() = widened.head<kLinkParameterCount>();
  out.tail(rest) = widened.tail(rest);
  return out;
}

FloatingPhysicalEstimate fitFloatingPhysical(const FloatingModel& model, const BaseParameters& base,
                                             SensorSet set,
                                             const std::vector<FloatingMeasurement>& samples,
                                             const ChannelVariances& variances,
                                             const Eigen::VectorXd& prior,
                                             const PhysicalOptions& options) {
  const int p = model.numParameters();
  if (prior.size() != p)
    throw InputError("a floating prior needs " + std::to_string(p) + " parameters, not " +
                     std::to_string(prior.size()));
  // The problem's layout: the base body as body 0 with the limbs' drive terms too (d columns the
  // data never reach: the prior holds them at their scale and nothing else sees them).
  const ParameterLayout& limbs = model.limbs().parameterLayout();
  const ParameterLayout layout{limbs.num_links + 1, limbs.drives};
  const int rest = p - kLinkParameterCount;
  const auto widened = [&](const Eigen::VectorXd& theta) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(layout.size());
    out.head<kLinkParameterCount>() = theta.head<kLinkParameterCount>();
    out.tail(rest) = theta.tail(rest);
    return out;
  };
  const Eigen::MatrixXd R = floatingStandardFactor(set, samples, &variances);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p, layout.size());
  A.leftCols<kLinkParameterCount>() = R.topLeftCorner(p, kLinkParameterCount);
  A.rightCols(rest) = R.block(0, kLinkParameterCount, p, rest);
  const auto problem = std::make_shared<const PhysicalProblem>(makePhysicalProblem(
      layout, std::move(A), R.col(p).head(p), widened(prior), options.prior_weight));
  Eigen::VectorXd start = problem->prior;  // inside the physical set; F is strictly convex
  for (Eigen::Index k = 0; k < start.size(); ++k)
    if (problem->positive[static_cast<std::size_t>(k)])
      start[k] = std::max(start[k], 1e-2 * problem->scales[k]);
  const PhysicalSolution solution = solvePhysicalProblem(*problem, start, options);
  FloatingPhysicalEstimate out;
  out.theta = narrowFloating(solution.theta, p);
  out.beta = base.project(out.theta);
  out.problem = problem;
  out.widened = solution.theta;
  out.unexplained = 0.5 * R(p, p) * R(p, p);
  out.converged = solution.converged;
  out.termination = solution.termination;
  out.iterations = solution.iterations;
  return out;
}

}  // namespace dynid
