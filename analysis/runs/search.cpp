#include "analysis/runs/search.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "analysis/estimation/pipeline.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/records/search_record.hpp"
#include "analysis/records/upgrade.hpp"
#include "analysis/runs/arm.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/perturb.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"
#include "data/robots.hpp"

namespace dynid {

// ---- the GC-error searches ----

namespace {
/// makeGcProblem, its refusals (irregular time, too few samples for a segment) naming the file.
GcProblem gcProblemOf(const Trajectory& data, const SegmentOptions& segments,
                      const std::string& file) {
  try {
    return makeGcProblem(data, segments);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}
}  // namespace

GcProblem heldOutProblem(const std::string& file, int num_joints, const SegmentOptions& segments) {
  return gcProblemOf(readDatasetCsv(file, num_joints), segments, file);
}

std::pair<double, double> heldOutGc(const Model& first, const Model& second, const GcProblem& test,
                                    int threads) {
  ThreadPool pool(resolveThreads(threads));
  GcWorkspace workspace(pool.numThreads());
  const double a = gcError(first, test, workspace, pool);
  return {a, gcError(second, test, workspace, pool)};
}

SearchOutcome searchRun(const SearchRequest& request) {
  request.check();
  const Model& robot = request.robot;
  if (!isSearch(request.method))
    throw InputError(std::string("'") + methodName(request.method) + "' is not a search (" +
                     methodList(searchMethods()) + ")");
  SearchBudget budget = request.budget;
  if (budget.max_evaluations == 0 && budget.max_seconds == 0 && budget.gc_tolerance <= 0)
    budget.max_seconds = 60.0;  // never run unbounded
  const std::string& mass = request.mass_constraint;

  Model initial = request.init.value_or(robot);
  if (request.perturb) initial = perturbedModel(robot, *request.perturb, request.seed);
  const Model* truth = request.truth ? &*request.truth : nullptr;
  for (const Model* m : {static_cast<const Model*>(&initial), truth})
    if (m != nullptr && (m->numJoints() != robot.numJoints() || m->parents() != robot.parents()))
      throw InputError("the initial and true models must have the robot's kinematic structure");

  SegmentOptions segments = request.segments;
  segments.seed = request.seed;
  const GcProblem problem = gcProblemOf(
      request.data ? *request.data : readDatasetCsv(request.data_file, robot.numJoints()), segments,
      request.data_file);
  std::optional<GcProblem> test;
  if (!request.validate_file.empty())
    test = heldOutProblem(request.validate_file, robot.numJoints(), segments);
  EstimationProblem estimation;
  estimation.model = robot;
  estimation.train_gc = &problem;
  estimation.start = initial;
  estimation.space = request.space;
  estimation.mass_plane = mass == "on"    ? MassPlane::kOn
                          : mass == "off" ? MassPlane::kOff
                                          : MassPlane::kAuto;
  estimation.total_mass =
      request.total_mass.value_or(totalMass(request.truth ? *request.truth : initial));
  estimation.search_budget = budget;
  estimation.seed = request.seed;
  estimation.ga = request.ga;
  estimation.nlo = request.nlo;
  estimation.threads = resolveThreads(request.threads);
  estimation.control = request.control;
  SearchOutcome out;
  Eigen::VectorXd truth_full;
  estimation.on_search_iteration = [&](Method, const SearchState& state, const ParameterSpace&) {
    if (!request.checkpoint.empty())
      writeFileAtomically(request.checkpoint, jsonText(checkpointJson(state, out.settings)) + "\n",
                          ExistingTarget::kUpdate);  // the checkpoint it resumed from
    if (request.on_iteration) request.on_iteration(state);
  };
  estimation.truth_full = request.truth ? &truth_full : nullptr;
  MethodRunner runner(std::move(estimation));
  out.robot = robot.name;
  out.model = robot;
  out.source = request.robot_source.spec.empty() ? ModelSource{robot.name, "", ""}  // in memory
                                                 : request.robot_source;
  out.method = request.method;
  out.space = runner.sharedSpace(request.method);
  const ParameterSpace& space = *out.space;
  if (request.truth) truth_full = space.fullVector(*request.truth);

  SearchSettingsRecord record{space.options(), space.freeNames(), segments,    request.seed,
                              budget,          request.ga,        request.nlo, request.data_file};
  record.segments.num_segments = problem.numSegments();
  record.segments.step = problem.step;
  out.settings = searchSettingsJson(record);
  // Checkpoints resume only runs with the same settings (threads may differ: results do not).
  const std::optional<SearchState> resume =
      readCheckpoint(request.checkpoint, out.settings, methodName(request.method));
  runner.setResume(resume ? &*resume : nullptr);
  runner.run(request.method);
  out.result = *runner.searchResult(request.method);
  const Eigen::VectorXd x_initial = space.project(space.initial());
  if (request.truth) {
    out.initial_parameter_error = space.parameterError(x_initial, truth_full);
    out.final_parameter_error = space.parameterError(out.result.best_x, truth_full);
  }
  if (!request.validate_file.empty()) {
    out.validate_file = request.validate_file;
    std::tie(out.validate_initial_gc, out.validate_final_gc) =
        heldOutGc(space.modelAt(x_initial), space.modelAt(out.result.best_x), *test,
                  runner.pool().numThreads());
  }
  return out;
}

// ---- refinement ----

namespace {

/// What the start document says of itself: the robot it embeds must be `robot` (same kinematics),
/// and an earlier version is read as it is, with a warning.
void checkStart(const RefineStart& start, const std::string& file, const Model& robot,
                std::vector<std::string>& warnings) {
  if (start.made_on) {
    const std::string difference = kinematicsDifference(*start.made_on, robot, "its robot");
    if (!difference.empty())
      throw InputError(file + " was made on another robot than '" + robot.name +
                       "' (`robot`): " + difference);
  }
  const DocumentType& type = start.kind == "search" ? kSearchDocument : kEstimateDocument;
  if (start.version < type.schema_version)
    warnings.push_back(olderVersionNote(file, type.kind, start.version, type.schema_version));
}

}  // namespace

RefineOutcome refineRun(const RefineRequest& request) {
  request.check();
  const Model& robot = request.robot;
  RefineOutcome out;
  out.robot = robot.name;
  out.model = robot;
  out.source = request.robot_source.spec.empty() ? ModelSource{robot.name, "", ""}  // in memory
                                                 : request.robot_source;
  out.from_file = request.from_file;
  out.data_file = request.data_file;
  out.options = request.options;
  out.options.num_threads = resolveThreads(request.options.num_threads);
  out.options.control = request.control;

  // The search's space and segments (search.json), or the request's (estimate.json).
  SpaceOptions space_options;
  space_options.form = request.form;
  space_options.relative_range = request.range;
  SegmentOptions segment_options;
  segment_options.horizon = request.horizon;
  segment_options.num_segments = request.segments;
  const RefineStart start = refineStartFrom(
      request.from_document ? *request.from_document
                            : parseJson(readFile(request.from_file), request.from_file),
      request.from_file, robot, space_options, segment_options);
  checkStart(start, request.from_file, robot, out.warnings);
  out.from_kind = start.kind;
  out.segment_options = start.segments;
  out.space = std::make_shared<const ParameterSpace>(start.initial, start.space);
  const ParameterSpace& space = *out.space;
  out.x0 = space.project(space.freeOf(space.fullVector(start.estimate)));
  const GcProblem problem = gcProblemOf(
      request.data ? *request.data : readDatasetCsv(request.data_file, robot.numJoints()),
      start.segments, request.data_file);
  out.num_segments = problem.numSegments();
  std::optional<GcProblem> test;
  if (!request.validate_file.empty())
    test = heldOutProblem(request.validate_file, robot.numJoints(), start.segments);
  if (request.truth && request.truth->parameterLayout().size() != robot.parameterLayout().size())
    throw InputError("the true model has another parameter layout than the robot");
  // Base coordinates from the structural analysis (the same defaults as dynid identifiability).
  out.base = structuralBaseParameters(robot);
  EstimationProblem estimation;
  estimation.model = robot;
  estimation.base = &out.base;
  estimation.train_gc = &problem;
  estimation.refine.options = out.options;
  estimation.threads = out.options.num_threads;
  estimation.control = request.control;
  MethodRunner runner(std::move(estimation));
  out.result = runner.refineFrom(space, out.x0);
  out.beta0 = out.base.project(space.standardAt(out.x0));

  const RefineResult& result = out.result;
  if (out.options.estimate_initial_states) {
    Eigen::VectorXd shift(problem.numSegments());
    for (int s = 0; s < problem.numSegments(); ++s) {
      Eigen::VectorXd measured(2 * robot.numJoints());
      measured << problem.data.q.col(problem.starts[s]), problem.data.dq.col(problem.starts[s]);
      shift[s] = (result.initial_states.col(s) - measured).norm();
    }
    out.rms_start_shift = std::sqrt(shift.squaredNorm() / problem.numSegments());
  }
  if (request.truth) {
    const Model& truth = *request.truth;
    out.has_truth = true;
    const Eigen::VectorXd truth_full = space.fullVector(truth);
    const Eigen::VectorXd beta_true = out.base.project(truth.standardParameters());
    out.initial_parameter_error = space.parameterError(out.x0, truth_full);
    out.final_parameter_error = space.parameterError(result.x, truth_full);
    out.initial_base_error = baseParameterError(out.beta0, beta_true);
    out.final_base_error = baseParameterError(result.beta, beta_true, &out.final_base_error_max);
    if (result.base_stage)
      out.base_stage_base_error = baseParameterError(result.base_beta, beta_true);
  }
  if (!request.validate_file.empty()) {
    out.validate_file = request.validate_file;
    std::tie(out.validate_initial_gc, out.validate_final_gc) =
        heldOutGc(space.modelAt(out.x0), space.modelAt(result.x), *test, out.options.num_threads);
  }
  return out;
}

}  // namespace dynid
