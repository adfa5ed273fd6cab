#include "analysis/demo.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "core/controllers.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/puma560.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/physically_consistent.hpp"
#include "search/optimizers.hpp"
#include "search/refine.hpp"

namespace dynid {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The default sinusoidal tracking run of `dynid simulate` (train) or the held-out control path
/// of docs/SEARCH.md's default scenario (test).
Trajectory simulateRun(const Model& truth, double duration, bool held_out) {
  const int n = truth.numJoints();
  SinusoidalReference r;
  r.q0 = defaultCentre(truth);
  if (held_out) {
    r.amplitude = Eigen::VectorXd::Constant(n, 0.7);
    r.frequency.resize(n);
    const double f[] = {0.27, 0.19, 0.41, 0.33, 0.6, 0.5};
    for (int i = 0; i < n; ++i) r.frequency[i] = f[i % 6];
    r.phase = Eigen::VectorXd::Constant(n, 0.5);
  } else {
    r.amplitude = Eigen::VectorXd::Constant(n, 0.5);
    r.frequency = defaultFrequencies(n);
    r.phase = Eigen::VectorXd::Zero(n);
  }
  Eigen::VectorXd tau_max(n);
  for (int i = 0; i < n; ++i) tau_max[i] = truth.limits[i].effort;
  TrackingController controller(truth, r, defaultGains(truth, r.q0, 5.0), tau_max);
  SimulationOptions options;
  options.duration = duration;
  return simulate(truth, controller, options);
}

double totalMass(const Model& model) {
  double total = 0.0;
  for (const auto& inertia : model.inertias) total += inertia.mass;
  return total;
}

}  // namespace

DemoResult runDemo(const DemoOptions& options) {
  const auto start = Clock::now();
  const auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto stopped = [&] { return options.stop != nullptr && options.stop->load(); };
  DemoResult result;
  DemoSettings& settings = result.settings;
  settings.quick = options.quick;
  settings.seed = options.seed;
  settings.train_seconds = settings.test_seconds = options.quick ? 4.0 : 10.0;
  settings.segments = options.quick ? 20 : 100;
  settings.horizon = 0.05;
  settings.perturb = 0.3;
  settings.search_seconds =
      options.search_seconds > 0 ? options.search_seconds : (options.quick ? 2.0 : 30.0);
  settings.refine_iterations = options.quick ? 30 : 200;
  settings.threads = options.threads > 0
                         ? options.threads
                         : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  const Model truth = makePuma560();
  settings.robot = truth.name;
  const Model initial = perturbedModel(truth, settings.perturb, options.seed);
  say("simulating " + std::to_string(settings.train_seconds) + " s of training and held-out data");
  const Trajectory train_data = simulateRun(truth, settings.train_seconds, false);
  const Trajectory test_data = simulateRun(truth, settings.test_seconds, true);
  SegmentOptions segments;
  segments.horizon = settings.horizon;
  segments.num_segments = settings.segments;
  const GcProblem train = makeGcProblem(train_data, segments);
  const GcProblem test = makeGcProblem(test_data, segments);

  // Identifiability: structural base parameters from random states.
  say("base parameters");
  const ParameterLayout layout = truth.parameterLayout();
  const std::vector<std::string> names = standardParameterNames(layout);
  const BaseParameters base = computeBaseParameters(
      observationFromRandomStates(truth, std::max(100, 5 * layout.size() / truth.numJoints()), 1).W,
      names, 0.0, defaultPreference(layout.num_links, layout.perLink()));
  DemoIdentifiability& ident = result.identifiability;
  ident.num_standard = base.numStandard();
  ident.num_base = base.numBase();
  for (int j = 0; j < base.numBase(); ++j) {
    ident.base_names.push_back(base.baseName(j));
    ident.base_expressions.push_back(base.expression(j));
  }
  for (int k : base.zero_columns) ident.unidentifiable.push_back(names[k]);
  const Observation observation = observationFromTrajectory(truth, train_data);
  ident.condition_number = scaledConditionNumber(base.baseRegressor(observation.W));

  // The spaces the searches move in (the paper's form; NLO holds the total mass, GA does not).
  SpaceOptions nlo_space_options;
  nlo_space_options.total_mass_constraint = true;
  nlo_space_options.total_mass = totalMass(truth);
  const ParameterSpace nlo_space(initial, nlo_space_options);
  const ParameterSpace ga_space(initial, SpaceOptions{});
  ThreadPool pool(settings.threads);
  Comparison comparison(truth, ga_space, base, train, test, test_data, pool);
  const double initial_gc = comparison.trainGc(initial);
  const Eigen::VectorXd prior = initial.standardParameters();
  const auto modelWith = [&](const Eigen::VectorXd& theta) {
    Model m = truth;
    m.setStandardParameters(theta);
    return m;
  };

  // Least squares on the torques.
  for (const LeastSquaresMethod method :
       {LeastSquaresMethod::kOrdinary, LeastSquaresMethod::kWeighted}) {
    say(std::string("identify: ") + leastSquaresMethodName(method));
    const auto t0 = Clock::now();
    const BaseEstimate estimate = estimateBaseParameters(base, observation, method);
    const Model model = modelWith(base.standardFromBase(estimate.beta, prior));
    result.methods.push_back(
        comparison.measure(leastSquaresMethodName(method), model, initial_gc, 0, since(t0)));
  }
  if (!stopped()) {
    say("identify: pc (physically consistent)");
    const auto t0 = Clock::now();
    const PhysicalEstimate pc = estimatePhysicallyConsistent(base, observation, prior);
    result.methods.push_back(
        comparison.measure("pc", modelWith(pc.theta), initial_gc, pc.iterations, since(t0)));
  }

  // The paper's searches, then refinement of the NLO and GA results.
  const Eigen::VectorXd truth_full = ga_space.fullVector(truth);
  const auto search = [&](const std::string& method, const ParameterSpace& space) {
    say("search: " + method + " (" + std::to_string(settings.search_seconds) + " s)");
    SearchContext context;
    context.space = &space;
    context.problem = &train;
    context.pool = &pool;
    context.truth_full = &truth_full;
    context.budget.max_seconds = settings.search_seconds;
    context.seed = options.seed;
    context.stop = options.stop;
    return method == "nlo"  ? runNlo(context, NloOptions{})
           : method == "ga" ? runGa(context, GaOptions{})
                            : runHybrid(context, GaOptions{}, NloOptions{});
  };
  BaseCoordinates coordinates{base.projectionMatrix(), ident.base_names};
  std::vector<std::pair<std::string, SearchResult>> searches;
  for (const auto& [method, space] :
       {std::pair<std::string, const ParameterSpace*>{"nlo", &nlo_space},
        {"ga", &ga_space},
        {"hybrid", &nlo_space}}) {
    if (stopped()) break;
    SearchResult found = search(method, *space);
    result.methods.push_back(comparison.measure(method, space->modelAt(found.best_x), initial_gc,
                                                found.evaluations, found.seconds));
    searches.emplace_back(method, std::move(found));
  }
  for (const auto& [method, found] : searches) {
    if (method == "hybrid" || stopped()) continue;
    say("refine: " + method);
    const ParameterSpace& space = method == "nlo" ? nlo_space : ga_space;
    RefineOptions refine;
    refine.num_threads = settings.threads;
    refine.max_iterations = settings.refine_iterations;
    refine.stop = options.stop;
    const RefineResult refined = refineGc(space, train, found.best_x, refine, &coordinates);
    result.methods.push_back(
        comparison.measure(method + "_refined", space.modelAt(refined.x), refined.initial_gc,
                           refined.base_iterations + refined.iterations, refined.seconds));
  }
  result.interrupted = stopped();
  result.seconds = since(start);
  return result;
}

}  // namespace dynid
