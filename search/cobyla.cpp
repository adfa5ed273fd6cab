#include "search/cobyla.hpp"

#include <nlopt.hpp>

#include "core/errors.hpp"

namespace dynid {

namespace {

double objectiveOf(unsigned, const double* x, double*, void* raw) {
  const auto* problem = static_cast<const CobylaProblem*>(raw);
  const std::optional<double> f = problem->objective(x);
  if (!f) throw nlopt::forced_stop();  // NLopt ends the run and rethrows it from optimize()
  return *f;
}

void inequalityOf(unsigned, double* c, unsigned, const double* x, double*, void* raw) {
  static_cast<const CobylaProblem*>(raw)->inequality(x, c);
}

double equalityOf(unsigned, const double* x, double*, void* raw) {
  return static_cast<const CobylaProblem*>(raw)->equality(x);
}

}  // namespace

CobylaOutcome runCobyla(const CobylaProblem& problem, std::vector<double>& x) {
  const auto n = static_cast<std::size_t>(problem.dimension);
  const auto sized = [&](const std::vector<double>& v) { return v.empty() || v.size() == n; };
  if (problem.dimension < 1 || x.size() != n || !sized(problem.lower) || !sized(problem.upper) ||
      !(problem.initial_step.size() == 1 || problem.initial_step.size() == n) ||
      !problem.objective || (problem.inequalities > 0 && !problem.inequality))
    throw InputError("COBYLA: the start, bounds and steps must have the problem's dimension");
  nlopt::opt opt(nlopt::LN_COBYLA, static_cast<unsigned>(n));
  void* data = const_cast<CobylaProblem*>(&problem);  // NLopt's callbacks take void*
  opt.set_min_objective(objectiveOf, data);
  if (problem.inequalities > 0)
    opt.add_inequality_mconstraint(inequalityOf, data,
                                   std::vector<double>(problem.inequalities, 0.0));
  if (problem.equality) opt.add_equality_constraint(equalityOf, data, problem.equality_tolerance);
  if (!problem.lower.empty()) opt.set_lower_bounds(problem.lower);
  if (!problem.upper.empty()) opt.set_upper_bounds(problem.upper);
  if (problem.initial_step.size() == 1)
    opt.set_initial_step(problem.initial_step.front());
  else
    opt.set_initial_step(problem.initial_step);
  opt.set_maxeval(problem.max_evaluations);
  opt.set_xtol_rel(problem.xtol_rel);
  double value = 0.0;
  try {
    const nlopt::result result = opt.optimize(x, value);
    return {result == nlopt::MAXEVAL_REACHED ? CobylaEnd::kEvaluations : CobylaEnd::kConverged, ""};
  } catch (const nlopt::forced_stop&) {
    return {CobylaEnd::kStopped, ""};
  } catch (const nlopt::roundoff_limited&) {
    return {CobylaEnd::kRoundoff, ""};
  } catch (const std::exception& e) {
    // NLopt's failures, and what a callback threw (NLopt turns it into its own failure).
    return {CobylaEnd::kFailed, e.what()};
  }
}

}  // namespace dynid
