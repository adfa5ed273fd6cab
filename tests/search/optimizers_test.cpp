#include "search/optimizers.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include <cmath>
#include <functional>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// A planar 2R arm with gravity in the plane and its 7-parameter guess 20 % off.
struct SmallProblem {
  SmallProblem() {
    truth = test::Planar2R().model();
    SinusoidalReference r;
    r.q0 = Eigen::Vector2d(0.3, 0.5);
    r.amplitude = Eigen::Vector2d(1.0, 1.2);
    r.frequency = Eigen::Vector2d(0.4, 0.7);
    r.phase = Eigen::Vector2d(0.0, 1.0);
    TrackingController controller(truth, r, defaultGains(truth, r.q0), Eigen::Vector2d(1e9, 1e9));
    SimulationOptions options;
    options.duration = 4.0;
    problem =
        makeGcProblem(simulate(truth, controller, options), {.horizon = 0.1, .num_segments = 30});
  }
  Model truth;
  GcProblem problem;
};

SearchContext context(const ParameterSpace& space, const GcProblem& problem, ThreadPool& pool,
                      long evaluations, std::uint64_t seed = 1) {
  SearchContext c;
  c.space = &space;
  c.problem = &problem;
  c.pool = &pool;
  c.budget.max_evaluations = evaluations;
  c.seed = seed;
  return c;
}

TEST(Optimizers, NloAndGaFindTheKnownMinimum) {
  // Only the 6 base parameters of the arm matter; free the masses and COMs of a guess that is
  // wrong in exactly those, so the known minimum GC error is 0 at the truth's base values.
  const SmallProblem small;
  const Model guess = perturbedModel(small.truth, 0.2, 3);
  const ParameterSpace space(guess, {});
  ThreadPool pool(2);
  GcWorkspace workspace(2);
  const double start = gcError(space.modelAt(space.initial()), small.problem, workspace, pool);
  const SearchResult nlo = runNlo(context(space, small.problem, pool, 4000), {});
  // Known minimum 0: COBYLA reaches a tiny fraction of the starting error.
  EXPECT_LT(nlo.best_gc, 1e-6 * start) << nlo.best_gc << " from " << start;
  const SearchResult ga = runGa(context(space, small.problem, pool, 4000), {.population = 40});
  EXPECT_LT(ga.best_gc, 1e-2 * start) << ga.best_gc << " from " << start;
  EXPECT_EQ(ga.history.front().stage, "ga");
  EXPECT_EQ(ga.evaluations, 4000);  // the budget holds exactly, even mid-generation
}

TEST(Optimizers, EveryCandidateSatisfiesTheConstraints) {
  const SmallProblem small;
  const Model guess = perturbedModel(small.truth, 0.3, 5);
  const ParameterSpace space(guess, {.total_mass_constraint = true, .total_mass = 2.1});
  ThreadPool pool(1);
  int infeasible = 0, count = 0;
  for (const std::string method : {"nlo", "ga", "hybrid"}) {
    SearchContext c = context(space, small.problem, pool, 600);
    c.on_evaluation = [&](const Eigen::VectorXd& x, double) {
      ++count;
      if (!space.feasible(x)) ++infeasible;
    };
    if (method == "nlo") runNlo(c, {});
    if (method == "ga") runGa(c, {.population = 20});
    if (method == "hybrid") runHybrid(c, {.population = 20}, {});
  }
  EXPECT_GT(count, 1500);
  EXPECT_EQ(infeasible, 0);
}

TEST(Optimizers, SameSeedSameResultForOneOrTwoThreads) {
  const SmallProblem small;
  const ParameterSpace space(perturbedModel(small.truth, 0.3, 6), {});
  ThreadPool one(1), two(2);
  const SearchResult a = runGa(context(space, small.problem, one, 300, 9), {.population = 20});
  const SearchResult b = runGa(context(space, small.problem, two, 300, 9), {.population = 20});
  EXPECT_EQ(a.best_x, b.best_x);
  EXPECT_EQ(a.best_gc, b.best_gc);
  EXPECT_EQ(a.evaluations, b.evaluations);
  const SearchResult c = runNlo(context(space, small.problem, one, 500, 9), {});
  const SearchResult d = runNlo(context(space, small.problem, two, 500, 9), {});
  EXPECT_EQ(c.best_x, d.best_x);
  EXPECT_EQ(c.evaluations, 500);
  EXPECT_EQ(c.termination, "evaluations");
  const SearchResult e = runGa(context(space, small.problem, one, 300, 10), {.population = 20});
  EXPECT_NE(a.best_x, e.best_x);  // another seed, another search
}

TEST(Optimizers, DivergingCandidatesDoNotDerailTheSearch) {
  // Masses may reach 0 with zero inertia about the axis: some candidates make the mass matrix
  // singular and their rollouts non-finite. The GC error stays finite and the search improves.
  const SmallProblem small;
  Model guess = small.truth;
  const ParameterSpace space(guess, {.relative_range = 1.0});
  ThreadPool pool(2);
  int capped = 0;
  SearchContext c = context(space, small.problem, pool, 1500);
  c.on_evaluation = [&](const Eigen::VectorXd&, double gc) {
    EXPECT_TRUE(std::isfinite(gc));
    if (gc >= kMaxSegmentError) ++capped;
  };
  const SearchResult ga = runGa(c, {.population = 30, .mutation_rate = 0.5, .mutation_scale = 1.5});
  EXPECT_GT(capped, 0) << "no candidate diverged: the test does not test anything";
  EXPECT_LT(ga.best_gc, 1e-9);  // the truth (the start) stays the best, untouched by the NaNs
  const SearchResult nlo = runNlo(c, {.mutation_scale = 1.5});
  EXPECT_TRUE(std::isfinite(nlo.best_gc));
}

TEST(Optimizers, EveryCheckpointResumesToTheUninterruptedRun) {
  // Every state a search hands to its checkpoint (round 0 included, and the hybrid's GA-to-NLO
  // boundary) names its stage and resumes to exactly the uninterrupted run's result.
  const SmallProblem small;
  const ParameterSpace space(perturbedModel(small.truth, 0.3, 7), {});
  ThreadPool pool(1);
  const GaOptions ga{.population = 20};
  const NloOptions nlo{.evaluations_per_seed = 60};  // rounds of 180 evaluations
  const auto search = [&](const std::string& method, const SearchContext& c) {
    if (method == "nlo") return runNlo(c, nlo);
    if (method == "ga") return runGa(c, ga);
    return runHybrid(c, ga, nlo);
  };
  for (const std::string method : {"nlo", "ga", "hybrid"}) {
    const long budget = method == "hybrid" ? 500 : 360;
    std::vector<SearchState> saved;
    SearchContext first = context(space, small.problem, pool, budget, 4);
    first.on_iteration = [&](const SearchState& s) { saved.push_back(s); };
    const SearchResult whole = search(method, first);
    ASSERT_GE(saved.size(), 3u) << method;
    // Resumed from: the first two, the last, and the two either side of a stage change.
    std::set<std::size_t> picked = {0, 1, saved.size() - 1};
    std::set<std::string> stages;
    for (std::size_t k = 0; k < saved.size(); ++k) {
      ASSERT_TRUE(saved[k].stage == "nlo" || saved[k].stage == "ga") << method << " " << k;
      if (k > 0 && saved[k].stage != saved[k - 1].stage) picked.insert({k - 1, k});
    }
    for (const std::size_t k : picked) {
      SCOPED_TRACE(method + ", checkpoint " + std::to_string(k));
      stages.insert(saved[k].stage);
      SearchContext resumed = context(space, small.problem, pool, budget, 4);
      resumed.resume = &saved[k];
      const SearchResult rest = search(method, resumed);
      EXPECT_EQ(rest.best_x, whole.best_x);
      EXPECT_EQ(rest.evaluations, whole.evaluations);
      EXPECT_EQ(rest.history.size(), whole.history.size());
    }
    if (method == "hybrid") {
      EXPECT_EQ(stages.size(), 2u);  // both stages were resumed from
    }
  }
}

TEST(Optimizers, ACorruptCheckpointStateIsAnInputErrorNotACrash) {
  // A GA state saved after 2 generations of a 20-member population, then corrupted the ways a
  // hand-edited or truncated checkpoint can be: each must be refused before any generation runs.
  const SmallProblem small;
  const ParameterSpace space(perturbedModel(small.truth, 0.3, 7), {});
  ThreadPool pool(1);
  SearchState saved;
  int iterations = 0;
  SearchContext first = context(space, small.problem, pool, 200, 4);
  first.on_iteration = [&](const SearchState& s) {
    if (++iterations == 2) saved = s;
  };
  runGa(first, {.population = 20});
  ASSERT_EQ(saved.population.size(), 20u);
  const auto refused = [&](const std::function<void(SearchState&)>& corrupt) {
    SearchState bad = saved;
    corrupt(bad);
    SearchContext resumed = context(space, small.problem, pool, 400, 4);
    resumed.resume = &bad;
    EXPECT_THROW(runGa(resumed, {.population = 20}), InputError);
  };
  refused([](SearchState& s) { s.population.resize(5), s.population_gc.resize(5); });  // short
  refused([](SearchState& s) { s.population_gc.pop_back(); });
  refused([](SearchState& s) { s.population[3].resize(2); });
  refused([](SearchState& s) { s.population[0][0] = std::nan(""); });
  refused([](SearchState& s) { s.evaluations = -5; });
  // The intact state resumes.
  SearchContext resumed = context(space, small.problem, pool, 400, 4);
  resumed.resume = &saved;
  EXPECT_NO_THROW(runGa(resumed, {.population = 20}));
}

TEST(Optimizers, RejectsBadOptions) {
  const SmallProblem small;
  const ParameterSpace space(small.truth, {});
  ThreadPool pool(1);
  EXPECT_THROW(runGa(context(space, small.problem, pool, 10), {.population = 1}), InputError);
  EXPECT_THROW(runNlo(context(space, small.problem, pool, 10), {.evaluations_per_seed = 0}),
               InputError);
}

}  // namespace
}  // namespace dynid
