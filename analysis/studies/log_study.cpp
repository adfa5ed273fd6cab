#include "analysis/studies/log_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/estimation/front.hpp"
#include "analysis/estimation/pipeline.hpp"
#include "analysis/logs/rest.hpp"
#include "analysis/records/prepare_record.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "data/dataset_csv.hpp"
#include "search/refinement/combined.hpp"

namespace dynid {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The GC problem of a dataset with at most the requested segments (all it holds when fewer).
GcProblem gcProblem(const Trajectory& data, const SegmentOptions& options,
                    const std::string& file) {
  try {
    return makeGcProblemUpTo(data, options);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

}  // namespace

void LogStudyRequest::check() const {
  if (data_file.empty()) throw InputError("the study needs training data (`data`)");
  if (validate_file.empty()) throw InputError("the study needs held-out data (`validate`)");
  // The ranges of dynid study's options (core/option_ranges.hpp), by field name.
  checkOption("study", "horizon", segments.horizon, "`horizon`");
  checkOption("study", "segments", segments.num_segments, "`segments`");
  checkOption("study", "search-seconds", search_seconds, "`search_seconds`");
  checkOption("study", "search-evaluations", static_cast<double>(search_evaluations),
              "`search_evaluations`");
  if (search_seconds == 0.0 && search_evaluations == 0)
    throw InputError("a search needs a budget: search seconds or evaluations > 0");
  checkOption("study", "refine-iterations", refine_iterations, "`refine_iterations`");
  checkOption("study", "refine-seconds", refine_seconds, "`refine_seconds`");
  checkOption("study", "refine-tolerance", refine_tolerance, "`refine_tolerance`");
  checkOption("study", "prior-weight", prior_weight, "`prior_weight`");
  checkOption("study", "combined-weight", combined_weight, "`combined_weight`");
  checkOption("study", "front-tolerance", front_tolerance, "`front_tolerance`");
  if (!front_weights.empty()) checkFrontWeights(front_weights);
  checkOption("study", "threads", threads, "`threads`");
  if (!write_back_from.empty() && front_weights.empty())
    throw InputError(
        "`write_back_from` writes the estimate chosen from the front: it needs "
        "`front_weights`");
}

StudyChoice studyChoice(const LogStudyOutcome& outcome, double tolerance) {
  // The candidates: the rows but the searches' start (pc's estimate), then the front's points.
  std::vector<std::pair<const LogStudyRow*, int>> rows;
  for (const LogStudyRow& row : outcome.rows)
    if (row.key != "start") rows.emplace_back(&row, -1);
  for (std::size_t k = 0; k < outcome.front.size(); ++k)
    rows.emplace_back(&outcome.front[k].row, static_cast<int>(k));
  std::vector<HeldOutErrors> errors;
  for (const auto& [row, index] : rows)
    errors.push_back({row->torque_test, row->gc_test, row->consistent, row->gc_floor_test});
  const FrontChoice c = chooseByHeldOut(errors, tolerance);
  StudyChoice out;
  if (c.best_torque < 0) return out;
  const auto keyOf = [&](int k) { return rows[k].second < 0 ? rows[k].first->key : "front"; };
  out.best_torque = keyOf(c.best_torque);
  out.best_front_index = rows[c.best_torque].second;
  out.torque_bound = c.torque_bound;
  out.at_floor = c.at_floor;
  out.key = keyOf(c.index);
  out.front_index = rows[c.index].second;
  return out;
}

const LogStudyRow* studyChosenRow(const LogStudyOutcome& outcome, const StudyChoice& choice) {
  if (choice.front_index >= 0) return &outcome.front[choice.front_index].row;
  for (const LogStudyRow& row : outcome.rows)
    if (!choice.key.empty() && row.key == choice.key) return &row;
  return nullptr;
}

StudyVerdict studyVerdict(const std::vector<LogStudyRow>& rows) {
  StudyVerdict out;
  double sim = 0.0, ctl = 0.0, tor = 0.0, gc = 0.0;
  const auto better = [](std::string& key, double& best, const LogStudyRow& row, double value) {
    if (!std::isfinite(value)) return;
    if (key.empty() || value < best) key = row.key, best = value;
  };
  const bool pc_row =
      std::any_of(rows.begin(), rows.end(), [](const LogStudyRow& row) { return row.key == "pc"; });
  for (const LogStudyRow& row : rows) {
    if (row.key == "start" && pc_row) continue;  // pc's estimate, under its own row
    if (!(std::isfinite(row.torque_test) && std::isfinite(row.gc_test))) continue;
    better(out.best_torque, tor, row, row.torque_test);
    better(out.best_gc, gc, row, row.gc_test);
    if (!row.consistent) continue;
    better(out.control, ctl, row, row.torque_test);
    better(out.simulation, sim, row, row.gc_test);
  }
  return out;
}

namespace {

/// The one pipeline's problem for the study's methods: the searches start from the physically
/// consistent estimate, the refinements and the combined estimator share the refine budget.
EstimationProblem studyProblem(const LogStudyRequest& request, const Model& robot,
                               const BaseParameters& base, const Observation& observation,
                               const GcProblem& train_gc, int threads) {
  EstimationProblem problem;
  problem.model = robot;
  problem.base = &base;
  problem.least_squares.observation = &observation;
  problem.physical.prior_weight = request.prior_weight;
  problem.train_gc = &train_gc;
  problem.search_start = SearchStart::kPhysicallyConsistent;
  problem.seed = request.seed;
  problem.setBudgets(request.search_seconds, request.search_evaluations, request.refine_iterations,
                     request.refine_seconds, request.refine_tolerance, request.keep_if_better);
  problem.combined.gc_weight = request.combined_weight;
  problem.combined.function_tolerance = request.refine_tolerance;
  problem.threads = threads;
  problem.control = request.control;
  return problem;
}

/// The outcome's record of what was studied and with which settings.
LogStudyOutcome settingsOf(const LogStudyRequest& request, const Model& robot) {
  LogStudyOutcome out;
  out.robot_spec = request.robot_spec;
  out.model = request.robot;
  out.source = request.robot_spec.empty() ? ModelSource{request.robot.name, "", ""}
                                          : modelSourceOf(request.robot_spec);
  out.data_file = request.data_file;
  out.validate_file = request.validate_file;
  out.drive_terms = driveTermsText(robot.driveTerms());
  out.segments = request.segments;
  out.prior_weight = request.prior_weight;
  out.combined_weight = request.combined_weight;
  out.refine_seconds = request.refine_seconds;
  out.refine_iterations = request.refine_iterations;
  out.front_tolerance = request.front_tolerance;
  return out;
}

using MeasureRow = std::function<LogStudyRow(const std::string&, const Model&, long, double)>;

/// The front's points (analysis/estimation/front.hpp) from pc, each measured as a method is.
std::vector<FrontRow> frontRows(const LogStudyRequest& request, const Model& robot,
                                const BaseParameters& base, const LeastSquaresSource& source,
                                const LeastSquaresOutcome& pc, const GcProblem& train_gc,
                                CombinedOptions options, int threads, const MeasureRow& measure) {
  options.num_threads = threads;
  options.control = request.control;
  std::vector<FrontRow> out;
  for (const FrontPoint& p :
       combinedFront(robot, base, source, pc, train_gc, options, request.front_weights)) {
    Model model = robot;
    model.setStandardParameters(p.estimate.standard);
    FrontRow row{p.weight, measure("front", model, p.detail.iterations, p.detail.seconds)};
    row.row.note = combinedNote(p.detail);
    row.row.moved = p.detail.moved;
    out.push_back(row);
  }
  return out;
}

/// The study's two datasets and their GC problems, and the held-out torque noise as its
/// preparation measured it, for each model's noise floor (a filtered log's residual differences
/// see little of the noise its rollouts integrate).
struct StudyData {
  Trajectory train, test;
  GcProblem train_gc, test_gc;
  std::optional<TorqueNoise> test_noise;
};
StudyData readStudyData(const LogStudyRequest& request) {
  const int n = request.robot.numJoints();
  StudyData d;
  d.train = readDatasetCsv(request.data_file, n);
  d.test = readDatasetCsv(request.validate_file, n);
  d.train_gc = gcProblem(d.train, request.segments, request.data_file);
  d.test_gc = gcProblem(d.test, request.segments, request.validate_file);
  d.test_noise = torqueNoiseOf(findPreparation(request.validate_file), d.test.meanRate(), n);
  return d;
}

/// The chosen estimate written into a copy of the URDF, when the request asks for it.
std::optional<WriteBack> chosenWriteBack(const LogStudyRequest& request, const LogStudyOutcome& out,
                                         const Model& robot) {
  if (request.write_back_from.empty() || out.front.empty()) return std::nullopt;
  const LogStudyRow* row = studyChosenRow(out, studyChoice(out, request.front_tolerance));
  if (row == nullptr) return std::nullopt;
  Model chosen = robot;
  chosen.setStandardParameters(row->standard);
  return estimateWriteBack(request.write_back_from, chosen, out.num_standard - out.num_base);
}

}  // namespace

LogStudyOutcome logStudyRun(const LogStudyRequest& request) {
  request.check();
  const auto t0 = Clock::now();
  const auto say = [&](const std::string& line) { request.control.say(line); };
  const auto stopped = [&] { return request.control.interrupted(); };
  const StudyData d = readStudyData(request);
  // Every model of the study, the input's included, is at rest within the training data's rest
  // velocities (as identify's estimates are).
  Model robot = request.robot;
  robot.rest_velocities = restThresholds(measureRestVelocities(d.train.dq, d.train.time));
  LogStudyOutcome out = settingsOf(request, robot);
  out.train_samples = d.train.numSamples();
  out.test_samples = d.test.numSamples();
  out.train_segments = d.train_gc.numSegments();
  out.test_segments = d.test_gc.numSegments();
  out.horizon = request.segments.horizon;
  const int threads = resolveThreads(request.threads);
  ThreadPool pool(threads);  // the measurements'; the runner has its own
  GcWorkspace workspace(threads);

  say("base parameters and the least-squares estimates");
  const BaseParameters base = structuralBaseParameters(robot);
  out.num_base = base.numBase();
  out.num_standard = base.numStandard();
  const Observation observation = observationFromTrajectory(robot, d.train);
  const auto measure = [&](const std::string& key, const Model& model, long evaluations,
                           double seconds) {
    LogStudyRow row;
    row.key = key;
    const Prediction fit = predictTorques(model, d.train);
    row.torque_train = fit.validation.relative_error;
    if (out.fit_reversals.samples == 0 && (key == "ols" || key == "wls" || key == "pc"))
      out.fit_reversals = reversalResidual(fit);
    row.torque_test = predictTorques(model, d.test).validation.relative_error;
    row.gc_train = gcError(model, d.train_gc, workspace, pool);
    row.gc_test = gcError(model, d.test_gc, workspace, pool);
    row.gc_floor_test =
        gcNoiseFloor(model, d.test_gc, 8, threads, d.test_noise ? &*d.test_noise : nullptr);
    row.consistent = consistencyViolations(model).empty();
    row.standard = model.standardParameters();
    row.evaluations = evaluations;
    row.seconds = seconds;
    return row;
  };
  out.rows.push_back(measure("model", robot, 0, 0.0));

  // Every estimate comes from the one pipeline. The searches start from the physically consistent
  // estimate: the best torque fit that is a realisable body with friction that dissipates (the
  // input model often has no friction at all, and an OLS lift is rarely consistent, so rollouts
  // from either can diverge).
  EstimationProblem problem = studyProblem(request, robot, base, observation, d.train_gc, threads);
  const CombinedOptions combined = problem.combined;
  const LeastSquaresSource source = problem.least_squares;
  MethodRunner runner(std::move(problem));
  const std::vector<Method> methods = request.methods.empty() ? allMethods() : request.methods;
  const bool searching = std::any_of(methods.begin(), methods.end(),
                                     [](Method m) { return isSearch(m) || isRefined(m); });
  if (searching) out.rows.push_back(measure("start", runner.searchStart(), 0, 0.0));
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const Method method = methods[k];
    if (stopped()) {
      out.interrupted = true;
      break;
    }
    say(std::string(methodName(method)) + ", method " + std::to_string(k + 1) + " of " +
        std::to_string(methods.size()) + "; " +
        progressText(static_cast<double>(k) / static_cast<double>(methods.size()), since(t0)) +
        " (of the methods)");
    const Estimate estimate = runner.run(method);
    LogStudyRow row =
        measure(methodName(method), estimate.model, estimate.evaluations, estimate.seconds);
    row.note = estimate.note;
    row.moved = estimate.moved;
    out.rows.push_back(row);
  }
  if (!request.front_weights.empty() && !stopped() && !out.interrupted) {
    say("the front: combined at " + std::to_string(request.front_weights.size()) +
        " GC weights, each from the last");
    out.front = frontRows(request, robot, base, source, runner.leastSquares(Method::kPc),
                          d.train_gc, combined, threads, measure);
  }
  out.interrupted = out.interrupted || stopped();
  out.write_back = chosenWriteBack(request, out, robot);
  out.seconds = since(t0);
  return out;
}

}  // namespace dynid
