// The paper's approach on the PUMA 560, then dynid's answer to it, with the library: search the
// GC error (how well a model predicts the recorded motion 50 ms ahead) by multistart COBYLA from a
// 30 % perturbed guess, then refine the search's result by Ceres least squares on the same
// residuals, in base-parameter coordinates. `dynid search` and `dynid refine` run the same steps
// (analysis/runs/runs.hpp, searchRun and refineRun).
//
//   example_search_then_refine
#include <cstdio>

#include "analysis/runs/search.hpp"
#include "analysis/runs/simulate.hpp"
#include "core/perturb.hpp"
#include "data/robots.hpp"

int main() {
  using namespace dynid;
  const Model truth = loadRobot("puma560");
  // 3 s of noise-free tracking data, 20 segments of 50 ms.
  SimulateRequest simulation;
  simulation.robot = truth;
  simulation.amplitude = Eigen::VectorXd::Constant(truth.numJoints(), 0.5);
  simulation.simulation.duration = 3.0;
  const GcProblem problem =
      makeGcProblem(simulateRun(simulation).trajectory, {.horizon = 0.05, .num_segments = 20});

  // The search's space: the paper's 7 parameters per link within +-50 % of the guess, the total
  // mass held (as the paper's NLO does).
  const Model guess = perturbedModel(truth, 0.3, 1);
  SpaceOptions space_options;
  space_options.total_mass_constraint = true;
  space_options.total_mass = totalMass(truth);
  const ParameterSpace space(guess, space_options);
  ThreadPool pool(1);
  SearchContext context;
  context.space = &space;
  context.problem = &problem;
  context.pool = &pool;
  context.budget.max_evaluations = 400;
  const SearchResult search = runNlo(context, NloOptions{});

  // Refinement in base coordinates: exact Jacobians through the Jet rollouts.
  const BaseParameters base = structuralBaseParameters(truth);
  const BaseCoordinates coordinates = base.coordinates();
  RefineOptions options;
  options.max_iterations = 30;
  const RefineResult refined = refineGc(space, problem, search.best_x, options, &coordinates);

  const Eigen::VectorXd beta_true = base.project(truth.standardParameters());
  const auto base_error = [&](const Eigen::VectorXd& x) {
    return baseParameterError(base.project(space.standardAt(x)), beta_true);
  };
  std::printf("%-22s %12s %22s\n", "", "GC error", "base-parameter error");
  std::printf("%-22s %12.3g %22.3g\n", "initial guess", search.initial_gc,
              base_error(space.project(space.initial())));
  std::printf("%-22s %12.3g %22.3g\n", "NLO, 400 evaluations", search.best_gc,
              base_error(search.best_x));
  std::printf("%-22s %12.3g %22.3g\n", "refined", refined.final_gc, base_error(refined.x));
  // The refinement must improve on the search it starts from.
  return refined.final_gc < search.best_gc ? 0 : 1;
}
