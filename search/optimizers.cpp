#include "search/optimizers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "search/cobyla.hpp"

namespace dynid {

namespace {

/// Counts evaluations, enforces the budgets and the stop flag, and tracks the best candidate and
/// the smallest parameter error since the last history entry.
class Evaluator {
 public:
  Evaluator(const SearchContext& context, SearchState& state)
      : context_(context),
        space_(*context.space),
        state_(state),
        workspace_(context.pool->numThreads()),
        scratch_(context.space->modelAt(context.space->initial())),
        start_(std::chrono::steady_clock::now()),
        seconds_offset_(state.seconds),
        // The budget left after a resumed run's seconds; a spent budget stops at once.
        gc_control_(
            context.budget.max_seconds > 0.0
                ? context.control.within(
                      std::max(context.budget.max_seconds - seconds_offset_, 1e-300), start_)
                : context.control) {}

  /// GC error at the feasible point x (projected by the caller). An evaluation cut short by the
  /// stop flag or the time budget counts for nothing and returns +inf; stopReason() then says why.
  double evaluate(const Eigen::VectorXd& x) {
    space_.apply(x, scratch_);
    const double gc = gcError(scratch_, *context_.problem, workspace_, *context_.pool, gc_control_);
    if (std::isnan(gc)) return INFINITY;
    ++state_.evaluations;
    if (context_.on_evaluation) context_.on_evaluation(x, gc);
    if (gc < state_.best_gc) {
      state_.best_gc = gc;
      state_.best_x = x;
    }
    if (context_.truth_full != nullptr) {
      const double pe = space_.parameterError(x, *context_.truth_full);
      min_parameter_error_ = std::min(min_parameter_error_, pe);
      if (evaluated_.size() < 2'000'000) evaluated_.emplace_back(gc, pe);
    }
    return gc;
  }

  double seconds() const {
    return seconds_offset_ +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  /// Why the search must stop now, or "" to go on.
  std::string stopReason() const {
    const SearchBudget& b = context_.budget;
    if (context_.control.stopped())
      return context_.control.interrupted() ? "interrupted" : "seconds";
    if (state_.best_gc <= b.gc_tolerance) return "tolerance";
    if (b.max_evaluations > 0 && state_.evaluations >= b.max_evaluations) return "evaluations";
    if (b.max_seconds > 0.0 && seconds() >= b.max_seconds) return "seconds";
    return "";
  }

  /// Appends a history entry for this round or generation and reports the state.
  void record(const std::string& stage, double extra_min_parameter_error = INFINITY) {
    HistoryEntry h;
    h.stage = stage;
    h.iteration = state_.iteration;
    h.best_gc = state_.best_gc;
    if (context_.truth_full != nullptr) {
      h.best_parameter_error = space_.parameterError(state_.best_x, *context_.truth_full);
      h.min_parameter_error = std::min(min_parameter_error_, extra_min_parameter_error);
    }
    h.evaluations = state_.evaluations;
    h.seconds = seconds();
    state_.seconds = h.seconds;
    state_.history.push_back(h);
    min_parameter_error_ = INFINITY;
    if (context_.on_iteration) context_.on_iteration(state_);
  }

  double parameterError(const Eigen::VectorXd& x) const {
    return context_.truth_full ? space_.parameterError(x, *context_.truth_full) : NAN;
  }

  std::vector<std::pair<double, double>>& evaluated() { return evaluated_; }

 private:
  const SearchContext& context_;
  const ParameterSpace& space_;
  SearchState& state_;
  GcWorkspace workspace_;
  Model scratch_;
  std::chrono::steady_clock::time_point start_;
  double seconds_offset_;
  RunControl gc_control_;  // the caller's, with the search's time budget as a deadline
  double min_parameter_error_ = INFINITY;
  std::vector<std::pair<double, double>> evaluated_;
};

std::string saveRng(const std::mt19937_64& rng) {
  std::ostringstream s;
  s << rng;
  return s.str();
}
void loadRng(const std::string& text, std::mt19937_64& rng) {
  std::istringstream s(text);
  s >> rng;
  if (!s) throw InputError("checkpoint: the random generator state is corrupt");
}

/// x (1 + N(0, scale)) on every parameter; a parameter at 0 moves by scale times its range.
Eigen::VectorXd mutateAll(const ParameterSpace& space, const Eigen::VectorXd& x, double scale,
                          std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd y = x;
  for (Eigen::Index p = 0; p < x.size(); ++p) {
    const double magnitude =
        x[p] != 0.0 ? std::abs(x[p]) : 0.5 * (space.upper()[p] - space.lower()[p]);
    y[p] += scale * magnitude * normal(rng);
  }
  return space.project(y);
}

SearchState initialState(const SearchContext& context, const std::string& method) {
  if (context.resume != nullptr) {
    if (context.resume->method != method)
      throw InputError("the checkpoint is for method '" + context.resume->method + "', not '" +
                       method + "'");
    const SearchState& r = *context.resume;
    const int k = context.space->numFree();
    if (r.best_x.size() != k)
      throw InputError("the checkpoint has " + std::to_string(r.best_x.size()) +
                       " free parameters, this search " + std::to_string(k));
    // A corrupt or hand-edited state must fail here, not deep inside a generation.
    if (r.evaluations < 0 || r.iteration < 0 || !(r.seconds >= 0.0))
      throw InputError("the checkpoint's evaluations, iteration and seconds must be >= 0");
    if (r.population_gc.size() != r.population.size())
      throw InputError("the checkpoint has " + std::to_string(r.population.size()) +
                       " population members but " + std::to_string(r.population_gc.size()) +
                       " GC errors for them");
    for (std::size_t i = 0; i < r.population.size(); ++i)
      if (r.population[i].size() != k || !r.population[i].allFinite())
        throw InputError("the checkpoint's population member " + std::to_string(i) + " has " +
                         std::to_string(r.population[i].size()) +
                         " entries or a non-finite one; this search has " + std::to_string(k) +
                         " free parameters");
    return r;
  }
  SearchState state;
  state.method = method;
  state.best_x = context.space->project(context.space->initial());
  return state;
}

SearchResult finishRun(SearchState& state, Evaluator& evaluator, const std::string& termination) {
  SearchResult result;
  result.method = state.method;
  result.termination = termination.empty() ? "completed" : termination;
  result.best_x = state.best_x;
  result.initial_gc = state.initial_gc;
  result.best_gc = state.best_gc;
  result.evaluations = state.evaluations;
  result.seconds = evaluator.seconds();
  result.history = state.history;
  result.evaluated = std::move(evaluator.evaluated());
  return result;
}

// ---------------------------------------------------------------------------------------------
// NLO: each round optimises the current best and two mutations of it with COBYLA and keeps the
// best of the three.

/// One COBYLA run from `seed` on the evaluator's GC error: it evaluates the feasible point
/// nearest COBYLA's (bounds, mass plane) and penalises the distance to it. Returns its best point
/// and GC error.
std::pair<Eigen::VectorXd, double> cobyla(Evaluator& evaluator, const ParameterSpace& space,
                                          const NloOptions& options, const Eigen::VectorXd& seed,
                                          double penalty_scale) {
  const int n = space.numFree();
  Eigen::VectorXd best_x = seed;
  double best_gc = INFINITY;
  const Eigen::VectorXd range = space.upper() - space.lower();
  CobylaProblem problem;
  problem.dimension = n;
  problem.objective = [&](const double* x) -> std::optional<double> {
    const Eigen::Map<const Eigen::VectorXd> xv(x, n);
    const Eigen::VectorXd y = space.project(xv);
    const double gc = evaluator.evaluate(y);
    if (gc < best_gc) best_gc = gc, best_x = y;
    // The budget ran out or the user interrupted: keep the best so far.
    if (!evaluator.stopReason().empty()) return std::nullopt;
    return gc + penalty_scale * (xv - y).cwiseQuotient(range).squaredNorm();
  };
  if (space.options().total_mass_constraint) {
    problem.equality = [&](const double* x) {
      return space.totalMass(Eigen::Map<const Eigen::VectorXd>(x, n)) - space.options().total_mass;
    };
    problem.equality_tolerance = 1e-9 * (1 + space.options().total_mass);
  }
  problem.lower.assign(space.lower().data(), space.lower().data() + n);
  problem.upper.assign(space.upper().data(), space.upper().data() + n);
  const Eigen::VectorXd step = options.initial_step * range;
  problem.initial_step.assign(step.data(), step.data() + n);
  problem.max_evaluations = options.evaluations_per_seed;
  problem.xtol_rel = 1e-10;
  std::vector<double> x(seed.data(), seed.data() + n);
  const CobylaOutcome outcome = runCobyla(problem, x);
  if (outcome.end == CobylaEnd::kFailed) throw NumericalError("COBYLA failed: " + outcome.message);
  return {best_x, best_gc};
}

void nloRounds(const SearchContext& context, const NloOptions& options, SearchState& state,
               Evaluator& evaluator, std::mt19937_64& rng, std::string& termination) {
  const ParameterSpace& space = *context.space;
  const double penalty_scale =
      std::isfinite(state.initial_gc) ? std::max(state.initial_gc, 1e-12) : 1.0;
  state.stage = "nlo";
  while ((termination = evaluator.stopReason()).empty()) {
    // The current best and two mutations of it.
    const Eigen::VectorXd current = state.best_x;
    const Eigen::VectorXd seeds[3] = {current,
                                      mutateAll(space, current, options.mutation_scale, rng),
                                      mutateAll(space, current, options.mutation_scale, rng)};
    for (const Eigen::VectorXd& seed : seeds) {
      if (!evaluator.stopReason().empty()) break;
      cobyla(evaluator, space, options, seed, penalty_scale);
    }
    ++state.iteration;
    state.rng = saveRng(rng);
    evaluator.record("nlo");
  }
}

void checkNlo(const NloOptions& o) {
  if (o.evaluations_per_seed < 1 || !(o.mutation_scale >= 0) || !(o.initial_step > 0))
    throw InputError("NLO options: evaluations per seed >= 1, mutation scale >= 0, step > 0");
}

// ---------------------------------------------------------------------------------------------
// GA: roulette-wheel selection on 1 / GC, uniform crossover, per-parameter Gaussian mutation,
// migration away from the centroid, elitism.

void checkGa(const GaOptions& o) {
  if (o.population < 2 || o.elites < 0 || o.elites >= o.population || !(o.crossover_rate >= 0) ||
      o.crossover_rate > 1 || !(o.mutation_rate >= 0) || o.mutation_rate > 1 ||
      !(o.mutation_scale >= 0) || !(o.migration >= 0))
    throw InputError(
        "GA options: population >= 2, 0 <= elites < population, rates in [0, 1], "
        "scales >= 0");
}

void gaGenerations(const SearchContext& context, const GaOptions& options, SearchState& state,
                   Evaluator& evaluator, std::mt19937_64& rng, std::string& termination,
                   long evaluation_limit, double seconds_limit) {
  const ParameterSpace& space = *context.space;
  auto limit_reached = [&] {
    termination = evaluator.stopReason();
    if (!termination.empty()) return true;
    return (evaluation_limit > 0 && state.evaluations >= evaluation_limit) ||
           (seconds_limit > 0 && evaluator.seconds() >= seconds_limit);
  };
  state.stage = "ga";
  std::vector<Eigen::VectorXd>& population = state.population;
  std::vector<double>& fitness_gc = state.population_gc;
  if (population.empty()) {
    // Generation 0: the initial estimate and mutations of it.
    population.push_back(state.best_x);
    while (static_cast<int>(population.size()) < options.population)
      population.push_back(mutateAll(space, state.best_x, options.mutation_scale, rng));
    for (const Eigen::VectorXd& x : population) fitness_gc.push_back(evaluator.evaluate(x));
    state.rng = saveRng(rng);
    evaluator.record("ga");
  }
  const int P = options.population;
  if (static_cast<int>(population.size()) != P || fitness_gc.size() != population.size())
    throw InputError("the resumed population has " + std::to_string(population.size()) +
                     " members and " + std::to_string(fitness_gc.size()) +
                     " GC errors; the GA's population is " + std::to_string(P));
  for (const Eigen::VectorXd& x : population)
    if (x.size() != space.numFree())
      throw InputError("a resumed population member has " + std::to_string(x.size()) +
                       " parameters, the search " + std::to_string(space.numFree()));
  while (!limit_reached()) {
    // Fresh distributions each generation: std::normal_distribution caches a second value, which a
    // checkpoint (the generator's state only) could not restore.
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    // Roulette wheel on fitness 1 / GC.
    std::vector<double> cumulative(P);
    double total = 0.0;
    for (int i = 0; i < P; ++i) cumulative[i] = total += 1.0 / std::max(fitness_gc[i], 1e-300);
    auto pick = [&] {
      const double r = unit(rng) * total;
      return static_cast<int>(std::lower_bound(cumulative.begin(), cumulative.end(), r) -
                              cumulative.begin());
    };
    std::vector<int> order(P);
    for (int i = 0; i < P; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return fitness_gc[a] < fitness_gc[b]; });
    std::vector<Eigen::VectorXd> next;
    std::vector<double> next_gc;
    for (int e = 0; e < options.elites; ++e) {
      next.push_back(population[order[e]]);
      next_gc.push_back(fitness_gc[order[e]]);
    }
    while (static_cast<int>(next.size()) < P) {
      const Eigen::VectorXd& a = population[std::min(pick(), P - 1)];
      const Eigen::VectorXd& b = population[std::min(pick(), P - 1)];
      Eigen::VectorXd child = a;
      if (unit(rng) < options.crossover_rate)
        for (Eigen::Index p = 0; p < child.size(); ++p) child[p] = unit(rng) < 0.5 ? a[p] : b[p];
      for (Eigen::Index p = 0; p < child.size(); ++p)
        if (unit(rng) < options.mutation_rate) {
          const double magnitude =
              child[p] != 0.0 ? std::abs(child[p]) : 0.5 * (space.upper()[p] - space.lower()[p]);
          child[p] += options.mutation_scale * magnitude * normal(rng);
        }
      next.push_back(space.project(child));
      next_gc.push_back(NAN);
    }
    // Migration: move every non-elite away from the population's centroid.
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(space.numFree());
    for (const Eigen::VectorXd& x : next) centroid += x;
    centroid /= P;
    for (int i = options.elites; i < P; ++i)
      next[i] = space.project(centroid + (1.0 + options.migration) * (next[i] - centroid));
    // Evaluate the new individuals; a budget cut mid-generation keeps the old ones.
    double elite_min_pe = INFINITY;
    for (int e = 0; e < options.elites; ++e)
      elite_min_pe = std::min(elite_min_pe, evaluator.parameterError(next[e]));
    bool cut = false;
    for (int i = options.elites; i < P && !cut; ++i) {
      next_gc[i] = evaluator.evaluate(next[i]);
      cut = !evaluator.stopReason().empty();
    }
    if (cut) {
      // A budget or an interrupt mid-generation: keep the last complete generation (the best
      // candidate evaluated is still kept by the evaluator).
      termination = evaluator.stopReason();
      break;
    }
    population = std::move(next);
    fitness_gc = std::move(next_gc);
    ++state.iteration;
    state.rng = saveRng(rng);
    evaluator.record("ga", elite_min_pe);
  }
}

}  // namespace

namespace {

/// The state, evaluator and generator of one search, started afresh (the initial estimate
/// evaluated) or resumed from a checkpoint.
struct Run {
  Run(const SearchContext& context, const std::string& method)
      : state(initialState(context, method)), evaluator(context, state), rng(context.seed) {
    if (!state.rng.empty()) loadRng(state.rng, rng);
    if (std::isnan(state.initial_gc)) state.initial_gc = evaluator.evaluate(state.best_x);
  }
  bool fresh() const { return state.history.empty() && state.population.empty(); }
  SearchResult finish() { return finishRun(state, evaluator, termination); }

  SearchState state;
  Evaluator evaluator;
  std::mt19937_64 rng;
  std::string termination;
};

}  // namespace

SearchResult runNlo(const SearchContext& context, const NloOptions& options) {
  checkNlo(options);
  Run run(context, "nlo");
  if (run.fresh()) {
    run.state.stage = "nlo";  // the first checkpoint (round 0) must name its stage to resume
    run.state.rng = saveRng(run.rng);
    run.evaluator.record("nlo");
  }
  nloRounds(context, options, run.state, run.evaluator, run.rng, run.termination);
  return run.finish();
}

SearchResult runGa(const SearchContext& context, const GaOptions& options) {
  checkGa(options);
  Run run(context, "ga");
  gaGenerations(context, options, run.state, run.evaluator, run.rng, run.termination, 0, 0.0);
  return run.finish();
}

SearchResult runHybrid(const SearchContext& context, const GaOptions& ga, const NloOptions& nlo) {
  checkGa(ga);
  checkNlo(nlo);
  Run run(context, "hybrid");
  // GA for half of each budget, then NLO from the GA's best (state.best_x).
  if (run.state.stage != "nlo") {
    const SearchBudget& b = context.budget;
    gaGenerations(context, ga, run.state, run.evaluator, run.rng, run.termination,
                  b.max_evaluations > 0 ? b.max_evaluations / 2 : 0,
                  b.max_seconds > 0 ? b.max_seconds / 2 : 0.0);
    run.state.population.clear();
    run.state.population_gc.clear();
  }
  if (run.termination.empty()) {
    run.state.iteration = 0;
    nloRounds(context, nlo, run.state, run.evaluator, run.rng, run.termination);
  }
  return run.finish();
}

}  // namespace dynid
