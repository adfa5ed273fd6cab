#include "identifiability/physically_consistent.hpp"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>
#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/log_cholesky.hpp"

namespace dynid {

namespace {

/// Residuals of the physically consistent problem for any Scalar (double or ceres::Jet).
struct PhysicalFunctor {
  PhysicalProblem problem;

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    const ParameterLayout& layout = problem.layout;
    const int per = layout.perLink(), p = layout.size();
    // theta from the log-Cholesky and drive blocks.
    VectorX<T> theta(p);
    for (int i = 0; i < layout.num_links; ++i) {
      theta.template segment<10>(i * per) = logCholeskyToStandard(blocks[i]);
      for (int k = 0; k < per - kLinkParameterCount; ++k)
        theta[i * per + kLinkParameterCount + k] = blocks[layout.num_links + i][k];
    }
    // Data term (R P theta - c) / sigma.
    const int b = static_cast<int>(problem.c.size());
    VectorX<T> beta(b);
    for (int j = 0; j < b; ++j) {
      T sum(0.0);
      for (int k = 0; k < p; ++k)
        if (problem.P(j, k) != 0.0) sum += problem.P(j, k) * theta[k];
      beta[j] = sum;
    }
    const double inv_sigma = 1.0 / problem.sigma;
    for (int j = 0; j < b; ++j) {
      T sum(-problem.c[j]);
      for (int k = j; k < b; ++k) sum += problem.R(j, k) * beta[k];
      residuals[j] = sum * inv_sigma;
    }
    // Prior term sqrt(lambda) (phi - phi_prior), drives scaled by their prior magnitudes.
    if (problem.prior_weight > 0.0) {
      const double w = std::sqrt(problem.prior_weight);
      int r = b;
      for (int i = 0; i < layout.num_links; ++i)
        for (int k = 0; k < kLogCholeskyCount; ++k)
          residuals[r++] = w * (blocks[i][k] - problem.prior_blocks[kLogCholeskyCount * i + k]);
      const int drive = per - kLinkParameterCount;
      for (int i = 0; i < layout.num_links && drive > 0; ++i)
        for (int k = 0; k < drive; ++k) {
          const int index = kLogCholeskyCount * layout.num_links + drive * i + k;
          residuals[r++] = w * (blocks[layout.num_links + i][k] - problem.prior_blocks[index]) /
                           problem.drive_scales[drive * i + k];
        }
    }
    // An overflowing exp (a step far out in log-Cholesky coordinates) is an evaluation failure:
    // Ceres rejects the step and shrinks its trust region.
    using std::isfinite;
    for (int j = 0; j < b; ++j)
      if (!isfinite(residuals[j])) return false;
    return true;
  }
};

/// Typical magnitude of each standard parameter's kind in theta (RMS over links of the non-zero
/// values; 1 when all are zero).
Eigen::VectorXd kindScales(const ParameterLayout& layout, const Eigen::VectorXd& theta) {
  const int per = layout.perLink();
  auto kind = [](int k) { return k == 0 ? 0 : k <= 3 ? 1 : k <= 9 ? 2 : k - 7; };
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(8), count = Eigen::VectorXd::Zero(8);
  for (int i = 0; i < layout.size(); ++i)
    if (theta[i] != 0.0) sum[kind(i % per)] += theta[i] * theta[i], count[kind(i % per)] += 1;
  Eigen::VectorXd out(layout.size());
  for (int i = 0; i < layout.size(); ++i) {
    const int k = kind(i % per);
    out[i] = count[k] > 0 ? std::sqrt(sum[k] / count[k]) : 1.0;
  }
  return out;
}

class IterateCallback : public ceres::IterationCallback {
 public:
  IterateCallback(const ParameterLayout& layout, const Eigen::VectorXd& x,
                  const std::function<void(const Eigen::VectorXd&)>& on_iterate)
      : layout_(layout), x_(x), on_iterate_(on_iterate) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    on_iterate_(standardFromPhysicalBlocks(layout_, x_));
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const ParameterLayout& layout_;
  const Eigen::VectorXd& x_;
  const std::function<void(const Eigen::VectorXd&)>& on_iterate_;
};

}  // namespace

std::vector<int> PhysicalProblem::blockSizes() const {
  std::vector<int> sizes(layout.num_links, kLogCholeskyCount);
  if (layout.drives)
    sizes.insert(sizes.end(), layout.num_links, layout.perLink() - kLinkParameterCount);
  return sizes;
}

int PhysicalProblem::numResiduals() const {
  return static_cast<int>(c.size()) +
         (prior_weight > 0.0 ? static_cast<int>(prior_blocks.size()) : 0);
}

PhysicalProblem makePhysicalProblem(const BaseParameters& base, const Observation& observation,
                                    const Eigen::VectorXd& prior, double prior_weight,
                                    double sigma) {
  if (prior.size() != base.numStandard())
    throw InputError("the prior has " + std::to_string(prior.size()) + " parameters, expected " +
                     std::to_string(base.numStandard()));
  if (!(prior_weight >= 0.0) || !std::isfinite(prior_weight))
    throw InputError("the prior weight must be finite and >= 0");
  if (!(sigma > 0.0)) throw InputError("sigma must be positive");
  const int p = base.numStandard();
  const int per = p / std::max(observation.num_joints, 1);
  PhysicalProblem problem;
  problem.layout = {observation.num_joints, per > kLinkParameterCount,
                    per > kLinkParameterCount + 3};
  if (problem.layout.size() != p)
    throw InputError("the base parameters do not match the observation's joint count");
  // Q R = W1; c = Q^T tau (the thin part).
  const Eigen::MatrixXd W1 = base.baseRegressor(observation.W);
  const int b = base.numBase();
  if (W1.rows() < b) throw InputError("fewer torque rows than base parameters");
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W1);
  problem.R = qr.matrixQR().topRows(b).triangularView<Eigen::Upper>();
  problem.c = (qr.householderQ().transpose() * observation.tau).head(b);
  problem.sigma = sigma;
  problem.P = base.projectionMatrix();
  problem.prior_weight = prior_weight;
  // The prior in the solver's coordinates: each link moved well inside the consistent set.
  Eigen::VectorXd consistent_prior = prior;
  const int per_link = problem.layout.perLink();
  for (int i = 0; i < problem.layout.num_links; ++i)
    consistent_prior.segment<10>(i * per_link) =
        nearestConsistent(prior.segment<10>(i * per_link).eval(), 1e-2);
  problem.prior_blocks = physicalBlocksFromStandard(problem.layout, consistent_prior);
  const Eigen::VectorXd scales = kindScales(problem.layout, prior);
  const int drive = per_link - kLinkParameterCount;
  problem.drive_scales.resize(problem.layout.num_links * drive);
  for (int i = 0; i < problem.layout.num_links; ++i)
    for (int k = 0; k < drive; ++k)
      problem.drive_scales[drive * i + k] = scales[i * per_link + kLinkParameterCount + k];
  return problem;
}

std::unique_ptr<ceres::CostFunction> makePhysicalCost(const PhysicalProblem& problem) {
  // Stride 10: one pass per link block.
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<PhysicalFunctor, 10>>(
      new PhysicalFunctor{problem});
  for (int size : problem.blockSizes()) cost->AddParameterBlock(size);
  cost->SetNumResiduals(problem.numResiduals());
  return cost;
}

Eigen::VectorXd standardFromPhysicalBlocks(const ParameterLayout& layout,
                                           const Eigen::VectorXd& blocks) {
  const int per = layout.perLink(), drive = per - kLinkParameterCount;
  if (blocks.size() != layout.num_links * (kLogCholeskyCount + drive))
    throw InputError("wrong number of physically consistent parameters");
  Eigen::VectorXd theta(layout.size());
  for (int i = 0; i < layout.num_links; ++i) {
    theta.segment<10>(i * per) = logCholeskyToStandard(blocks.data() + kLogCholeskyCount * i);
    theta.segment(i * per + kLinkParameterCount, drive) =
        blocks.segment(kLogCholeskyCount * layout.num_links + drive * i, drive);
  }
  return theta;
}

Eigen::VectorXd physicalBlocksFromStandard(const ParameterLayout& layout,
                                           const Eigen::VectorXd& theta) {
  const int per = layout.perLink(), drive = per - kLinkParameterCount;
  if (theta.size() != layout.size()) throw InputError("wrong number of standard parameters");
  Eigen::VectorXd blocks(layout.num_links * (kLogCholeskyCount + drive));
  for (int i = 0; i < layout.num_links; ++i) {
    blocks.segment<10>(kLogCholeskyCount * i) = standardToLogCholesky(theta.segment<10>(i * per));
    blocks.segment(kLogCholeskyCount * layout.num_links + drive * i, drive) =
        theta.segment(i * per + kLinkParameterCount, drive);
  }
  return blocks;
}

PhysicalEstimate estimatePhysicallyConsistent(const BaseParameters& base,
                                              const Observation& observation,
                                              const Eigen::VectorXd& prior,
                                              const PhysicalOptions& options) {
  PhysicalEstimate out;
  out.ols = estimateBaseParameters(base, observation, LeastSquaresMethod::kOrdinary);
  const Eigen::MatrixXd W1 = base.baseRegressor(observation.W);
  const int b = base.numBase();
  const auto rows = static_cast<double>(W1.rows());
  // sigma from the OLS residuals, floored at 1e-6 of the torques' RMS: with exact (noise-free)
  // data the prior term must keep a weight that holds the directions the data cannot see.
  const double tau_rms = observation.tau.norm() / std::sqrt(std::max(rows, 1.0));
  const double sigma_ols =
      std::max((W1 * out.ols.beta - observation.tau).norm() / std::sqrt(std::max(rows - b, 1.0)),
               1e-6 * tau_rms + 1e-300);
  const PhysicalProblem problem =
      makePhysicalProblem(base, observation, prior, options.prior_weight, sigma_ols);
  const ParameterLayout& layout = problem.layout;
  const int per = layout.perLink(), drive = per - kLinkParameterCount;

  // Starts, each link moved inside the consistent set by a margin (1e-2 of the normalised
  // pseudo-inertia, where the log-Cholesky coordinates are well conditioned) and Ia, Fv, Fc >= 0:
  // OLS lifted with the prior's dependent parameters, and the prior itself. A lift whose dependent
  // parameters are far off can land where Levenberg-Marquardt stalls, so both are solved and the
  // lower cost is kept.
  const auto consistentStart = [&](Eigen::VectorXd theta, std::vector<int>* moved) {
    for (int i = 0; i < layout.num_links; ++i) {
      const Eigen::Matrix<double, 10, 1> link = theta.segment<10>(i * per);
      const Eigen::Matrix<double, 10, 1> fixed = nearestConsistent(link, 1e-2);
      if (moved != nullptr && fixed != link) moved->push_back(i);
      theta.segment<10>(i * per) = fixed;
      for (int k = 0; k < std::min(drive, 3); ++k)
        theta[i * per + kLinkParameterCount + k] =
            std::max(theta[i * per + kLinkParameterCount + k], 0.0);
    }
    return theta;
  };
  const std::vector<Eigen::VectorXd> starts = {
      consistentStart(base.standardFromBase(out.ols.beta, prior), &out.inconsistent_links),
      consistentStart(prior, nullptr)};

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = 1e-16;
  solver.parameter_tolerance = 1e-14;
  solver.num_threads = std::max(options.num_threads, 1);
  solver.logging_type = ceres::SILENT;
  Eigen::VectorXd x;
  ceres::Solver::Summary summary;
  for (const Eigen::VectorXd& start : starts) {
    Eigen::VectorXd y = physicalBlocksFromStandard(layout, start);
    // One residual block over every parameter block; drive Ia, Fv, Fc >= 0.
    ceres::Problem solver_problem;
    std::vector<double*> pointers;
    int offset = 0;
    for (int size : problem.blockSizes()) pointers.push_back(y.data() + offset), offset += size;
    solver_problem.AddResidualBlock(makePhysicalCost(problem).release(), nullptr, pointers);
    for (int i = 0; i < layout.num_links && layout.drives; ++i)
      for (int k = 0; k < 3; ++k)
        solver_problem.SetParameterLowerBound(pointers[layout.num_links + i], k, 0.0);
    ceres::Solver::Options this_solver = solver;
    std::unique_ptr<IterateCallback> callback;
    if (options.on_iterate) {
      callback = std::make_unique<IterateCallback>(layout, y, options.on_iterate);
      this_solver.update_state_every_iteration = true;
      this_solver.callbacks.push_back(callback.get());
    }
    ceres::Solver::Summary this_summary;
    ceres::Solve(this_solver, &solver_problem, &this_summary);
    if (x.size() == 0 ||
        (this_summary.IsSolutionUsable() &&
         (!summary.IsSolutionUsable() || this_summary.final_cost < summary.final_cost))) {
      x = y;
      summary = this_summary;
      out.start_theta = start;
    }
  }

  out.theta = standardFromPhysicalBlocks(layout, x);
  out.beta = base.project(out.theta);
  for (const ceres::IterationSummary& it : summary.iterations) out.cost_history.push_back(it.cost);
  out.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " +
                    summary.message;
  out.usable = summary.IsSolutionUsable();
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  const std::vector<std::string> names = standardParameterNames(layout);
  for (int i = 0; i < layout.num_links && layout.drives; ++i)
    for (int k = 0; k < 3; ++k)
      if (out.theta[i * per + kLinkParameterCount + k] <= 0.0)
        out.at_bound.push_back(names[i * per + kLinkParameterCount + k]);

  // Residuals and the base covariance sigma^2 (R^T R)^-1 at the estimate.
  const Eigen::VectorXd residual = W1 * out.beta - observation.tau;
  const int n = observation.num_joints;
  out.residual_rms.resize(n);
  for (int j = 0; j < n; ++j) {
    double sum = 0.0;
    for (int k = 0; k < observation.num_samples; ++k)
      sum += residual[k * n + j] * residual[k * n + j];
    out.residual_rms[j] = std::sqrt(sum / std::max(observation.num_samples, 1));
  }
  const double sigma2 = residual.squaredNorm() / std::max(rows - b, 1.0);
  const Eigen::MatrixXd r_inv =
      problem.R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
  out.covariance = sigma2 * r_inv * r_inv.transpose();
  out.std_dev = out.covariance.diagonal().cwiseSqrt();
  return out;
}

}  // namespace dynid
