#include "search/refinement/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "search/refinement/costs.hpp"
#include "search/refinement/evaluation.hpp"
#include "search/refinement/uncertainty.hpp"

namespace dynid {

namespace {

/// Records each iteration, stops on the run control, and ends the stage before an iteration that
/// would overrun the time budget: when what is left of `budget` (RunControl::deadline) is less
/// than the longest iteration so far, the next one (a Jacobian of every segment, then trial steps)
/// would most likely end past it.
class RefineCallback : public ceres::IterationCallback {
 public:
  RefineCallback(std::vector<RefineIteration>& history, const RefineOptions& options,
                 const RunControl& budget, bool& interrupted, bool& out_of_time, std::string stage,
                 double time_offset, int reserved_iterations = 0)
      : history_(history),
        control_(options.control),
        on_iteration_(options.on_iteration),
        max_iterations_(options.max_iterations),
        budget_(budget),
        interrupted_(interrupted),
        out_of_time_(out_of_time),
        stage_(std::move(stage)),
        time_offset_(time_offset),
        reserved_(reserved_iterations) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    history_.push_back({stage_, summary.iteration, summary.cost, summary.gradient_max_norm,
                        time_offset_ + summary.cumulative_time_in_seconds});
    if (on_iteration_) {
      const double elapsed = history_.back().seconds;
      const double left =
          budget_.deadline == RunControl::Clock::time_point::max()
              ? -1.0
              : std::chrono::duration<double>(budget_.deadline - RunControl::Clock::now()).count();
      on_iteration_(history_.back(), left >= 0.0 ? elapsed / (elapsed + left)
                                                 : static_cast<double>(summary.iteration) /
                                                       std::max(max_iterations_, 1));
    }
    if (control_.check()) {
      interrupted_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    longest_ = std::max(longest_, summary.iteration_time_in_seconds);
    // Stop before an iteration that would end past the budget, leaving `reserved_` iterations'
    // time for what follows the stage (the uncertainty's Jacobian).
    if (budget_.deadline != RunControl::Clock::time_point::max() &&
        std::chrono::duration<double>(budget_.deadline - RunControl::Clock::now()).count() <
            longest_ * (1 + reserved_)) {
      out_of_time_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }
  /// The longest iteration so far [s] (a Jacobian of every segment, then trial steps).
  double longest() const { return longest_; }

 private:
  std::vector<RefineIteration>& history_;
  const RunControl& control_;
  const std::function<void(const RefineIteration&, double)>& on_iteration_;
  int max_iterations_;
  const RunControl& budget_;
  bool& interrupted_;
  bool& out_of_time_;
  std::string stage_;
  double time_offset_;
  int reserved_;
  double longest_ = 0.0;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The seconds the refinement may still run: its own budget (options.max_seconds from
/// clock_start) and the run control's deadline, whichever ends first; +inf without either.
double secondsLeft(const RefineOptions& options,
                   std::chrono::steady_clock::time_point clock_start) {
  double left = options.max_seconds > 0.0 ? options.max_seconds - secondsSince(clock_start)
                                          : std::numeric_limits<double>::infinity();
  if (options.control.deadline != RunControl::Clock::time_point::max())
    left = std::min(left, std::chrono::duration<double>(options.control.deadline -
                                                        std::chrono::steady_clock::now())
                              .count());
  return left;
}

/// Solver settings shared by the stages: Levenberg-Marquardt. Independent starts (when
/// estimated) are eliminated first by a block-sparse Schur complement; chained ones (a segment
/// ending on the next start, so no longer an independent set) go with the model parameters into a
/// sparse Cholesky factorisation of the normal equations, whose starts' part is block tridiagonal.
ceres::Solver::Options solverOptions(const RefineOptions& options, const GcProblem& problem,
                                     double* model_block, Eigen::MatrixXd& starts,
                                     double seconds_left) {
  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  const bool sparse = ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE);
  if (options.estimate_initial_states && anyChained(problem, options)) {
    solver.linear_solver_type = sparse ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  } else if (options.estimate_initial_states) {
    solver.linear_solver_type = sparse ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (int s = 0; s < starts.cols(); ++s) ordering->AddElementToGroup(starts.col(s).data(), 0);
    ordering->AddElementToGroup(model_block, 1);
    solver.linear_solver_ordering = ordering;
  } else {
    solver.linear_solver_type = ceres::DENSE_QR;
  }
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = options.gradient_tolerance;
  solver.parameter_tolerance = options.parameter_tolerance;
  if (std::isfinite(seconds_left)) solver.max_solver_time_in_seconds = std::max(seconds_left, 1e-3);
  // The parameters are the last accepted iterate even when an evaluation fails (a time budget
  // that ends inside an iteration makes every later evaluation fail, costs.hpp).
  solver.update_state_every_iteration = true;
  // The segments are evaluated on dynid's pool (ParallelSegmentEvaluation); Ceres on one thread
  // sums in the residual blocks' order, so the result is the same for any thread count.
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  return solver;
}

std::string terminationOf(const ceres::Solver::Summary& summary) {
  return std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " +
         summary.message;
}

/// The termination, saying so when the time budget ended the stage (an evaluation that failed
/// because the budget had run out is not a numerical failure).
std::string terminationAt(const ceres::Solver::Summary& summary, const RunControl& budget,
                          bool out_of_time) {
  const int iterations = std::max(static_cast<int>(summary.iterations.size()) - 1, 0);
  if (out_of_time)
    return "USER_SUCCESS: stopped after " + std::to_string(iterations) +
           " iterations: the next would end past its time budget";
  const bool failed = summary.termination_type == ceres::FAILURE ||
                      summary.termination_type == ceres::NO_CONVERGENCE;
  if (budget.expired() && failed)
    return "USER_SUCCESS: stopped at its time budget after " + std::to_string(iterations) +
           " iterations (" + summary.message + ")";
  if (budget.stopped() && failed)
    return "USER_SUCCESS: interrupted after " + std::to_string(iterations) + " iterations";
  return terminationOf(summary);
}

/// The map back's weighting R, for min |R (P theta(x) - beta)|^2 over x within the bounds: R^T R =
/// H the GC residuals' J^T J in beta at the solution: the Gauss-Newton model of the GC error's
/// increase, so that a beta the free parameters cannot reproduce exactly (noisy data) is approached
/// where the data determine it best. R is normalised to a unit misfit at the estimate. Should a
/// rollout diverge there, relative weights 1 / |beta| replace it.
Eigen::MatrixXd mapBackWeighting(const Model& structure, const BetaLift& map,
                                 const GcProblem& problem, const Eigen::VectorXd& beta,
                                 const Eigen::VectorXd& weights, const Eigen::MatrixXd& starts,
                                 const RefineOptions& options, ThreadPool& pool) {
  const int b = static_cast<int>(beta.size());
  Eigen::MatrixXd weighting = weights.asDiagonal();
  {
    double squared = 0.0;
    const Eigen::MatrixXd H =
        betaInformation(structure, map, problem, beta, starts, options, pool, squared);
    if (H.allFinite()) {
      Eigen::VectorXd d(b);
      for (int j = 0; j < b; ++j) d[j] = H(j, j) > 0.0 ? 1.0 / std::sqrt(H(j, j)) : 1.0;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(d.asDiagonal() * H *
                                                                 d.asDiagonal());
      const Eigen::VectorXd root = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
      const Eigen::MatrixXd r =
          root.asDiagonal() * eigen.eigenvectors().transpose() * d.cwiseInverse().asDiagonal();
      const double misfit = (r * (map.beta_ref - beta)).norm();
      if (misfit > 0.0 && std::isfinite(misfit)) weighting = r / misfit;
    }
  }
  return weighting;
}

/// The free parameters x within the bounds whose beta(x) is nearest the target, in the weighting
/// given: from the start, the box's centre and options.map_back_starts random points, the lowest
/// fit (within round-off) nearest the start.
Eigen::VectorXd fitFreeToBeta(const Model& structure, const ParameterSpace& space,
                              const Eigen::MatrixXd& weighted_projection,
                              const Eigen::VectorXd& weighted_target, const Eigen::VectorXd& start,
                              const RefineOptions& options, const RunControl& budget,
                              ThreadPool& pool) {
  const int k = space.numFree(), b = static_cast<int>(weighted_target.size());
  const int tries = 2 + std::max(options.map_back_starts, 0);
  std::vector<Eigen::VectorXd> fitted(tries);
  Eigen::VectorXd fit_cost(tries);
  std::mt19937_64 random(20260101);  // fixed: refinement is deterministic
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::VectorXd centre = 0.5 * (space.lower() + space.upper());
  const Eigen::VectorXd half_range = (0.5 * (space.upper() - space.lower())).cwiseMax(1e-300);
  for (int t = 0; t < tries; ++t) {
    fitted[t] = t == 0 ? start : centre;
    if (t > 1)
      for (int j = 0; j < k; ++j)
        fitted[t][j] = space.lower()[j] + uniform(random) * (space.upper()[j] - space.lower()[j]);
    fitted[t] = space.project(fitted[t]);
  }
  pool.parallelFor(tries, [&](int t, int) {
    Eigen::VectorXd& x = fitted[t];
    // The map is curved (products m c, m c c^T) and LM from a point alone stops at a bound: each
    // fit is a continuation, with a pull eps |(x - centre) / half range|^2 towards the box's
    // centre taken down from 1e-1 to 0.
    for (const double eps : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0}) {
      if (budget.stopped()) break;  // each fit so far is still a candidate
      auto fit = makeBetaOfFreeCost(structure, space, weighted_projection, weighted_target);
      ceres::Problem map_problem;
      map_problem.AddResidualBlock(fit.release(), nullptr, x.data());
      // The total mass weighted like the beta residuals (relative), for conditioning.
      if (space.options().total_mass_constraint)
        map_problem.AddResidualBlock(makeTotalMassCost(space, 1.0).release(), nullptr, x.data());
      if (eps > 0.0) {
        const Eigen::MatrixXd pull = eps * half_range.cwiseInverse().asDiagonal().toDenseMatrix();
        map_problem.AddResidualBlock(makeLinearCost(pull, pull * centre).release(), nullptr,
                                     x.data());
      }
      for (int j = 0; j < k; ++j) {
        map_problem.SetParameterLowerBound(x.data(), j, space.lower()[j]);
        map_problem.SetParameterUpperBound(x.data(), j, space.upper()[j]);
      }
      ceres::Solver::Options map_solver;
      map_solver.linear_solver_type = ceres::DENSE_QR;
      map_solver.max_num_iterations = 200;
      map_solver.function_tolerance = 1e-20;
      map_solver.gradient_tolerance = 1e-24;
      map_solver.parameter_tolerance = 1e-16;
      map_solver.logging_type = ceres::SILENT;
      if (budget.deadline != RunControl::Clock::time_point::max())  // a fit ends at the budget
        map_solver.max_solver_time_in_seconds = std::max(
            std::chrono::duration<double>(budget.deadline - RunControl::Clock::now()).count(),
            1e-3);
      ceres::Solver::Summary map_summary;
      ceres::Solve(map_solver, &map_problem, &map_summary);
    }
    fit_cost[t] = (weighted_projection * space.standardAt(x) - weighted_target).squaredNorm();
    if (space.options().total_mass_constraint)
      fit_cost[t] += std::pow(space.totalMass(x) / space.options().total_mass - 1.0, 2);
    if (!std::isfinite(fit_cost[t])) fit_cost[t] = std::numeric_limits<double>::infinity();
  });
  const double best = fit_cost.minCoeff();
  const Eigen::VectorXd x_scale = magnitudes(start);
  int chosen = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int t = 0; t < tries; ++t) {
    // "Best": within round-off of the lowest (b residuals of relative size ~1e-12).
    if (!(fit_cost[t] <= best * (1.0 + 1e-6) + 1e-24 * b)) continue;
    const double distance = (fitted[t] - start).cwiseQuotient(x_scale).norm();
    if (distance < nearest) nearest = distance, chosen = t;
  }
  return fitted[chosen];
}

/// The base stage: the GC residuals as a function of beta, solved by Levenberg-Marquardt from
/// beta(x); then x is fitted to the solution's beta within the bounds (and on the total-mass
/// plane). Updates result.x (when the map back predicts no worse than the start), the starts and
/// the base-stage fields. Returns the longest Jacobian of every segment it took [s].
double baseStage(const Model& structure, const ParameterSpace& space, const GcProblem& problem,
                 const BaseCoordinates& base, const RefineOptions& options,
                 std::chrono::steady_clock::time_point clock_start, const RunControl& budget,
                 GcWorkspace& workspace, ThreadPool& pool, RefineResult& result) {
  const bool with_start = options.estimate_initial_states;
  const Eigen::MatrixXd& P = base.projection;
  const Eigen::VectorXd theta0 = space.standardAt(result.x);
  const int b = static_cast<int>(P.rows());
  Eigen::VectorXd beta = P * theta0;
  const BetaLift map{theta0, beta, P.completeOrthogonalDecomposition().pseudoInverse()};

  ParallelSegmentEvaluation segments(pool);
  ceres::Problem::Options problem_options;
  problem_options.evaluation_callback = &segments;
  ceres::Problem beta_problem(problem_options);
  for (int s = 0; s < problem.numSegments(); ++s) {
    std::vector<double*> blocks =
        segmentBlocks(problem, options, s, beta.data(), result.initial_states);
    beta_problem.AddResidualBlock(
        segments
            .add(makeBetaSegmentCost(structure, map, problem, s, with_start,
                                     continuityOf(problem, options, s), &budget),
                 blocks)
            .release(),
        nullptr, blocks);
  }
  // Half of what is left, so that the map back and the parameter stage have their share.
  ceres::Solver::Options solver =
      solverOptions(options, problem, beta.data(), result.initial_states,
                    0.5 * secondsLeft(options, clock_start));
  bool base_out_of_time = false;
  RefineCallback callback(result.history, options, budget, result.interrupted, base_out_of_time,
                          "base", secondsSince(clock_start));
  solver.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &beta_problem, &summary);
  result.base_stage = true;
  result.base_beta = beta;
  result.base_termination = terminationAt(summary, budget, base_out_of_time);
  result.base_iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.initial_cost = summary.initial_cost;
  {
    Model at_beta = structure;
    at_beta.setStandardParameters(theta0 + map.lift * (beta - map.beta_ref));
    result.base_gc = gcError(at_beta, problem, workspace, pool);
  }

  // The map back takes a Jacobian and many small fits: not once the budget has run out, nor when
  // the base stage stopped because one more iteration (a Jacobian) would pass it; the free
  // parameters then stay where they were.
  if (budget.stopped() || base_out_of_time) return segments.longestJacobians();
  // Nor when what is left of the budget is less than one of the base stage's iterations: the
  // map back's Jacobian alone takes about that long.
  if (budget.deadline != RunControl::Clock::time_point::max() &&
      std::chrono::duration<double>(budget.deadline - RunControl::Clock::now()).count() <
          callback.longest())
    return segments.longestJacobians();
  const Eigen::VectorXd weights = magnitudes(beta).cwiseInverse();
  const Eigen::MatrixXd weighting = mapBackWeighting(structure, map, problem, beta, weights,
                                                     result.initial_states, options, pool);
  const Eigen::MatrixXd weighted_projection = weighting * P;
  const Eigen::VectorXd x = fitFreeToBeta(structure, space, weighted_projection, weighting * beta,
                                          result.x, options, budget, pool);
  result.map_back_error =
      (weights.cwiseProduct(P * space.standardAt(x) - beta)).norm() / std::sqrt(std::max(b, 1));
  // Keep the mapped-back point only when it predicts no worse than the start.
  const double gc_mapped = gcError(space.modelAt(x), problem, workspace, pool);
  result.map_back_used = std::isfinite(gc_mapped) && gc_mapped <= result.initial_gc;
  if (result.map_back_used) result.x = x;
  return segments.longestJacobians();
}

}  // namespace

namespace {

/// refineGc's checks of its arguments, and the result it starts from: the start projected onto the
/// space, the segments' measured initial states, the chained segments counted.
RefineResult startOfRefinement(const ParameterSpace& space, const GcProblem& problem,
                               const Eigen::VectorXd& x0, const RefineOptions& options,
                               const BaseCoordinates* base) {
  if (x0.size() != space.numFree())
    throw InputError("the start has " + std::to_string(x0.size()) + " free parameters, expected " +
                     std::to_string(space.numFree()));
  if (space.numFree() == 0) throw InputError("refinement needs at least one free parameter");
  if (!std::isfinite(options.continuity_weight) || options.continuity_weight < 0.0)
    throw InputError("the continuity weight must be a finite number >= 0");
  RefineResult result;
  result.x = space.project(x0);
  const Model structure = space.modelAt(result.x);
  const int n = structure.numJoints(), segments = problem.numSegments();
  if (problem.data.numJoints() != n)
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(n));
  if (base != nullptr && base->projection.cols() != structure.parameterLayout().size())
    throw InputError("the base coordinates have " + std::to_string(base->projection.cols()) +
                     " standard parameters, the model " +
                     std::to_string(structure.parameterLayout().size()));
  for (int s = 0; s < segments; ++s)
    if (continuityOf(problem, options, s) > 0.0) ++result.chained_segments;
  result.initial_states.resize(2 * n, segments);
  for (int s = 0; s < segments; ++s) {
    result.initial_states.col(s).head(n) = problem.data.q.col(problem.starts[s]);
    result.initial_states.col(s).tail(n) = problem.data.dq.col(problem.starts[s]);
  }
  return result;
}

/// The parameter stage's gauge: hold the current free directions (G (x - x_start) = 0, G their
/// scaled basis), so the solver does not drift along directions the data cannot see; a
/// zero-residual point with the gauge satisfied exists, so it biases nothing.
void addGauge(const Model& structure, const ParameterSpace& space, const BaseCoordinates& base,
              ceres::Problem& solver_problem, RefineResult& result) {
  const FreeAnalysis analysis = analyseFreeDirections(structure, space, base.projection, result.x);
  const int free = space.numFree() - analysis.rank;
  if (free <= 0) return;
  const double w = std::sqrt(std::max(result.initial_gc, 1e-300));
  const Eigen::MatrixXd g =
      w * analysis.v.rightCols(free).transpose() * analysis.x_scale.cwiseInverse().asDiagonal();
  solver_problem.AddResidualBlock(makeLinearCost(g, g * result.x).release(), nullptr,
                                  result.x.data());
  result.gauge_dimension = free;
}

/// How the parameter stage ended (`summary`, empty when it did not run), its costs, the final GC
/// error and the free parameters at a bound.
void endOfParameterStage(const ParameterSpace& space, const GcProblem& problem,
                         const ceres::Solver::Summary& summary, const RunControl& stage,
                         bool out_of_time, bool out_of_budget, GcWorkspace& workspace,
                         ThreadPool& pool, RefineResult& result) {
  if (summary.iterations.empty() && (result.interrupted || out_of_time)) {
    result.termination =
        result.interrupted
            ? std::string("USER_SUCCESS: interrupted ") +
                  (result.base_stage ? "in the base stage" : "before the parameter stage")
            : "USER_SUCCESS: the time budget ended before the parameter stage";
    result.usable = true;
  } else {
    result.termination = terminationAt(summary, stage, out_of_budget);
    result.usable = summary.IsSolutionUsable() || stage.stopped();
  }
  result.iterations = std::max(static_cast<int>(summary.iterations.size()) - 1, 0);
  if (!result.base_stage) result.initial_cost = summary.initial_cost;
  result.final_cost = summary.iterations.empty() ? result.initial_cost : summary.final_cost;
  result.final_gc = gcError(space.modelAt(result.x), problem, workspace, pool);
  const std::vector<std::string> names = space.freeNames();
  for (int j = 0; j < space.numFree(); ++j) {
    const double tolerance = 1e-9 * (space.upper()[j] - space.lower()[j]);
    if (result.x[j] - space.lower()[j] <= tolerance || space.upper()[j] - result.x[j] <= tolerance)
      result.at_bound.push_back(names[j]);
  }
}

}  // namespace

RefineResult refineGc(const ParameterSpace& space, const GcProblem& problem,
                      const Eigen::VectorXd& x0, const RefineOptions& options,
                      const BaseCoordinates* base) {
  const auto clock_start = std::chrono::steady_clock::now();
  RefineResult result = startOfRefinement(space, problem, x0, options, base);
  const Model structure = space.modelAt(result.x);
  const int segments = problem.numSegments();
  const bool with_start = options.estimate_initial_states;
  ThreadPool pool(std::max(options.num_threads, 1));
  GcWorkspace workspace(pool.numThreads());
  result.initial_gc = gcError(structure, problem, workspace, pool);
  // The time budget and the run control's deadline and flag, as the cost functions see them.
  const RunControl budget = options.control.within(options.max_seconds, clock_start);

  double jacobian_seconds = 0.0;  // the longest Jacobian of every segment so far [s]
  if (base != nullptr && options.base_stage)
    jacobian_seconds = baseStage(structure, space, problem, *base, options, clock_start, budget,
                                 workspace, pool, result);

  // The uncertainty pass after the parameter stage is one Jacobian of every segment: the stage
  // leaves it room inside the budget, the base stage's longest such Jacobian when it ran, else
  // one iteration of its own (its callback's reserve).
  const bool uncertainty = base != nullptr && options.uncertainty;
  // A quarter more than it took: Jacobians vary, and the stage's closing GC error comes first.
  const double reserve = uncertainty && options.max_seconds > 0.0 ? 1.25 * jacobian_seconds : 0.0;
  const RunControl stage =
      reserve > 0.0
          ? options.control.within(std::max(options.max_seconds - reserve, 1e-9), clock_start)
          : budget;

  // The parameter stage. Residual blocks: one per segment, and the total mass.
  ParallelSegmentEvaluation evaluation(pool);
  ceres::Problem::Options problem_options;
  problem_options.evaluation_callback = &evaluation;
  ceres::Problem solver_problem(problem_options);
  for (int s = 0; s < segments; ++s) {
    std::vector<double*> blocks =
        segmentBlocks(problem, options, s, result.x.data(), result.initial_states);
    solver_problem.AddResidualBlock(
        evaluation
            .add(makeSegmentCost(structure, space, problem, s, with_start,
                                 continuityOf(problem, options, s), &stage),
                 blocks)
            .release(),
        nullptr, blocks);
  }
  if (space.options().total_mass_constraint)
    solver_problem.AddResidualBlock(makeTotalMassCost(space).release(), nullptr, result.x.data());
  if (base != nullptr && options.fix_gauge)
    addGauge(structure, space, *base, solver_problem, result);
  for (int j = 0; j < space.numFree(); ++j) {
    solver_problem.SetParameterLowerBound(result.x.data(), j, space.lower()[j]);
    solver_problem.SetParameterUpperBound(result.x.data(), j, space.upper()[j]);
  }
  ceres::Solver::Options solver =
      solverOptions(options, problem, result.x.data(), result.initial_states,
                    secondsLeft(options, clock_start) - reserve);
  result.linear_solver = ceres::LinearSolverTypeToString(solver.linear_solver_type);
  bool out_of_budget = false;
  RefineCallback callback(result.history, options, stage, result.interrupted, out_of_budget,
                          "parameters", secondsSince(clock_start),
                          uncertainty && reserve == 0.0 ? 1 : 0);
  solver.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  const bool out_of_time = stage.expired();  // the base stage and the map back took it all
  // The run control (its flag, its deadline, its hook on this thread) may have ended a stage by
  // failing its evaluations (costs.hpp) rather than through the callback.
  if (options.control.check()) result.interrupted = true;
  if (!result.interrupted && !out_of_time) ceres::Solve(solver, &solver_problem, &summary);
  if (options.control.stopped()) result.interrupted = true;
  endOfParameterStage(space, problem, summary, stage, out_of_time, out_of_budget, workspace, pool,
                      result);
  // The uncertainty needs one more Jacobian (seconds): not after Ctrl-C, which must end the run
  // within a second with its best parameters, nor when the budget has no room left for it (a
  // stage that converged, or the base stage, close to the budget's end).
  if (base != nullptr) result.beta = base->projection * space.standardAt(result.x);
  if (uncertainty && !result.interrupted) {
    const double left = secondsLeft(options, clock_start),
                 needed = std::max(evaluation.longestJacobians(), jacobian_seconds);
    if (left >= needed && !budget.expired())
      baseUncertainty(structure, space, problem, *base, options, result, pool);
    else
      result.uncertainty_skipped =
          "the time budget left " + formatNumber(std::max(left, 0.0), 2) +
          " s, and the uncertainty needs a Jacobian of every segment (about " +
          formatNumber(needed, 2) + " s): raise the time budget for it";
  }
  result.seconds = secondsSince(clock_start);
  return result;
}

void silenceSolverLog() { FLAGS_minloglevel = google::GLOG_FATAL; }

}  // namespace dynid
