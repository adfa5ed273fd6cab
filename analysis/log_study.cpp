#include "analysis/log_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "search/parameter_space.hpp"
#include "search/refinement/refine.hpp"

namespace dynid {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void validate(const LogStudyRequest& r) {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError(what);
  };
  require(!r.data_file.empty(), "the study needs training data (--data)");
  require(!r.validate_file.empty(), "the study needs held-out data (--validate)");
  require(std::isfinite(r.search_seconds) && r.search_seconds >= 0.0,
          "search seconds must be >= 0");
  require(r.search_evaluations >= 0, "search evaluations must be >= 0");
  require(r.search_seconds > 0.0 || r.search_evaluations > 0,
          "a search needs a budget: search seconds or evaluations > 0");
  require(r.refine_iterations >= 1, "refine iterations must be >= 1");
  require(std::isfinite(r.refine_seconds) && r.refine_seconds >= 0.0,
          "refine seconds must be >= 0");
  require(std::isfinite(r.refine_tolerance) && r.refine_tolerance >= 0.0,
          "the refinement tolerance must be >= 0");
  require(r.threads >= 0, "threads must be >= 0");
}

/// The GC problem of a dataset with at most the requested segments (all it holds when fewer).
GcProblem gcProblem(const Trajectory& data, SegmentOptions options, const std::string& file) {
  try {
    if (!options.random_starts && options.num_segments > 0) {
      SegmentOptions all = options;
      all.num_segments = 0;
      options.num_segments = std::min(options.num_segments, makeGcProblem(data, all).numSegments());
    }
    return makeGcProblem(data, options);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

}  // namespace

LogStudyOutcome logStudyRun(const LogStudyRequest& request) {
  validate(request);
  const auto t0 = Clock::now();
  const auto say = [&](const std::string& line) {
    if (request.control.progress) request.control.progress(line);
  };
  const std::atomic<bool>* stop = request.control.stop;
  const auto stopped = [&] { return stop != nullptr && stop->load(); };
  const Model& robot = request.robot;
  const int n = robot.numJoints();
  LogStudyOutcome out;
  out.robot_spec = request.robot_spec;
  out.data_file = request.data_file;
  out.validate_file = request.validate_file;
  const Trajectory train = readDatasetCsv(request.data_file, n);
  const Trajectory test = readDatasetCsv(request.validate_file, n);
  out.train_samples = train.numSamples();
  out.test_samples = test.numSamples();
  const GcProblem train_gc = gcProblem(train, request.segments, request.data_file);
  const GcProblem test_gc = gcProblem(test, request.segments, request.validate_file);
  out.train_segments = train_gc.numSegments();
  out.test_segments = test_gc.numSegments();
  out.horizon = request.segments.horizon;
  const int threads = resolveThreads(request.threads);
  ThreadPool pool(threads);
  GcWorkspace workspace(threads);

  say("base parameters and the least-squares estimates");
  const BaseParameters base = structuralBaseParameters(robot);
  out.num_base = base.numBase();
  out.num_standard = base.numStandard();
  const Observation observation = observationFromTrajectory(robot, train);
  const auto modelWith = [&](const Eigen::VectorXd& theta) {
    Model m = robot;
    m.setStandardParameters(theta);
    return m;
  };
  const auto measure = [&](const std::string& key, const Model& model, long evaluations,
                           double seconds) {
    LogStudyRow row;
    row.key = key;
    row.torque_train = predictTorques(model, train).validation.relative_error;
    row.torque_test = predictTorques(model, test).validation.relative_error;
    row.gc_train = gcError(model, train_gc, workspace, pool);
    row.gc_test = gcError(model, test_gc, workspace, pool);
    row.consistent = consistencyViolations(model).empty();
    row.evaluations = evaluations;
    row.seconds = seconds;
    return row;
  };
  out.rows.push_back(measure("model", robot, 0, 0.0));

  // The searches start from the physically consistent estimate: the best torque fit that is a
  // realisable body with friction that dissipates (the input model often has no friction at all,
  // and an OLS lift is rarely consistent, so rollouts from either can diverge).
  std::map<Method, std::pair<LeastSquaresOutcome, double>> least_squares;
  const auto leastSquares = [&](Method method) -> const std::pair<LeastSquaresOutcome, double>& {
    const auto found = least_squares.find(method);
    if (found != least_squares.end()) return found->second;
    say(std::string("identify: ") + methodName(method));
    const auto started = Clock::now();
    LeastSquaresOutcome ls =
        estimateLeastSquares(method, base, observation, robot.standardParameters());
    return least_squares.emplace(method, std::make_pair(std::move(ls), since(started)))
        .first->second;
  };
  const std::vector<Method> methods = request.methods.empty() ? allMethods() : request.methods;
  const bool searching = std::any_of(methods.begin(), methods.end(),
                                     [](Method m) { return isSearch(m) || isRefined(m); });
  const Model start = searching ? modelWith(leastSquares(Method::kPc).first.standard) : robot;
  if (searching) out.rows.push_back(measure("start", start, 0, 0.0));

  SpaceOptions nlo_options;
  nlo_options.total_mass_constraint = true;
  nlo_options.total_mass = totalMass(start);
  const ParameterSpace nlo_space(start, nlo_options), ga_space(start, SpaceOptions{});
  const BaseCoordinates coordinates = base.coordinates();
  std::map<Method, SearchResult> searches;
  const auto search = [&](Method method) -> const SearchResult& {
    const auto found = searches.find(method);
    if (found != searches.end()) return found->second;
    say(std::string("search: ") + methodName(method) + " (" +
        (request.search_seconds > 0.0
             ? std::to_string(request.search_seconds) + " s"
             : std::to_string(request.search_evaluations) + " evaluations") +
        ")");
    SearchContext context;
    context.space = method == Method::kGa ? &ga_space : &nlo_space;
    context.problem = &train_gc;
    context.pool = &pool;
    context.budget.max_seconds = request.search_seconds;
    context.budget.max_evaluations = request.search_evaluations;
    context.seed = request.seed;
    context.stop = stop;
    return searches.emplace(method, runSearch(method, context, GaOptions{}, NloOptions{}))
        .first->second;
  };

  for (Method method : methods) {
    if (stopped()) {
      out.interrupted = true;
      break;
    }
    const std::string name = methodName(method);
    if (!isSearch(method) && !isRefined(method)) {
      const auto& [ls, seconds] = leastSquares(method);
      out.rows.push_back(
          measure(name, modelWith(ls.standard), ls.pc ? ls.pc->iterations : 0, seconds));
      continue;
    }
    const Method searched = searchOf(method);
    const ParameterSpace& space = searched == Method::kGa ? ga_space : nlo_space;
    const SearchResult& found = search(searched);
    if (isSearch(method)) {
      out.rows.push_back(
          measure(name, space.modelAt(found.best_x), found.evaluations, found.seconds));
      continue;
    }
    say(std::string("refine: ") + methodName(searched) + " (at most " +
        std::to_string(request.refine_iterations) + " iterations" +
        (request.refine_seconds > 0.0 ? ", " + std::to_string(request.refine_seconds) + " s"
                                      : std::string()) +
        ")");
    RefineOptions refine;
    refine.num_threads = threads;
    refine.max_iterations = request.refine_iterations;
    refine.max_seconds = request.refine_seconds;
    refine.function_tolerance = request.refine_tolerance;
    refine.stop = stop;
    const RefineResult refined = refineGc(space, train_gc, found.best_x, refine, &coordinates);
    LogStudyRow row = measure(name, space.modelAt(refined.x),
                              refined.base_iterations + refined.iterations, refined.seconds);
    // The refinement's start is the search's point projected onto the space (bounds, mass
    // plane); a refinement that ends above the search's own training GC error is not kept.
    const LogStudyRow searched_row = measure(methodName(searched), space.modelAt(found.best_x),
                                             found.evaluations, found.seconds);
    row.note = refined.termination + "; GC error from " + std::to_string(refined.initial_gc) +
               " to " + std::to_string(refined.final_gc);
    if (!(row.gc_train <= searched_row.gc_train)) {
      const std::string note = row.note;
      row = searched_row;
      row.key = name;
      row.evaluations = refined.base_iterations + refined.iterations;
      row.seconds = refined.seconds;
      row.note = "kept the search's result: the refinement did not lower its training GC error (" +
                 note + ")";
    }
    out.rows.push_back(row);
  }
  out.interrupted = out.interrupted || stopped();
  out.seconds = since(t0);
  return out;
}

}  // namespace dynid
