#include "analysis/runs/identify.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "analysis/runs/arm.hpp"
#include "analysis/runs/summarize.hpp"
#include "analysis/runs/training.hpp"
#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/dataset_csv.hpp"
#include "data/digest/sha256.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/urdf_writeback.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "search/gc_error.hpp"

namespace dynid {

IdentifiabilityOutcome identifiabilityRun(const Model& model, const StructuralOptions& structural,
                                          const std::string& data_file, int threads,
                                          const Trajectory* data) {
  IdentifiabilityOutcome out;
  out.structural = structural;
  out.base = structuralBaseParameters(model, structural);
  out.model_beta = out.base.project(model.standardParameters());
  // The conditioning on fresh random states (the next seed).
  const Observation check = observationFromRandomStates(
      model, std::max(100, out.base.numStandard()), structural.seed + 1);
  out.condition_number = scaledConditionNumber(out.base.baseRegressor(check.W));
  if (data || !data_file.empty()) {
    // Streamed: the base regressor's triangular factor, never the observation matrix.
    LeastSquaresStream stream(out.base, model);
    ThreadPool pool(threads);
    if (data)
      stream.addTrajectory(model, *data, &pool);
    else
      addDatasetFile(stream, model, data_file, pool);
    const LeastSquaresStream::Factor f = stream.factor();
    Eigen::VectorXd r_diagonal = f.r_scaled.diagonal().cwiseAbs();
    const bool full =
        stream.numSamples() * model.numJoints() >= out.base.numBase() && f.norms.minCoeff() > 0.0;
    out.data = DataExcitation{
        data_file, stream.numSamples(), excitationFromRDiagonal(r_diagonal),
        full ? conditionNumber(f.r_scaled) : std::numeric_limits<double>::infinity()};
  }
  return out;
}

// ---- identification ----

namespace {

/// A dataset's GC problem for the combined estimator, its refusals naming the file.
GcProblem combinedProblem(const IdentifyRequest& request, const Trajectory* given,
                          const std::string& file) {
  try {
    return makeGcProblemUpTo(
        given != nullptr ? *given : readDatasetCsv(file, request.model.numJoints()),
        request.segments);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

/// The held-out data as the combined estimator's summary and the front measure an estimate on it.
struct HeldOut {
  Trajectory data;
  GcProblem gc;
  std::optional<FitRows> rows;  // through the training torque's filter, when the fit reproduced one
  std::optional<TorqueNoise> noise;  // as its preparation measured it (prepare.json beside it)

  /// The held-out torque and GC errors of `model` with the parameters `standard`.
  HeldOutErrors errorsOf(Model model, const Eigen::VectorXd& standard, ThreadPool& pool,
                         GcWorkspace& workspace) const {
    model.setStandardParameters(standard);
    HeldOutErrors out;
    out.torque = predictTorques(model, data, &pool, nullptr, nullptr, rows ? &*rows : nullptr)
                     .validation.relative_error;
    out.gc = gcError(model, gc, workspace, pool);
    out.gc_floor = gcNoiseFloor(model, gc, 8, pool.numThreads(), noise ? &*noise : nullptr);
    out.consistent = consistencyViolations(model).empty();
    return out;
  }
};
std::optional<HeldOut> heldOutOf(const IdentifyRequest& request, const Model& model,
                                 const IdentifyOutcome& out) {
  if (request.validate == nullptr && request.validate_file.empty()) return std::nullopt;
  HeldOut held;
  held.data = request.validate != nullptr
                  ? *request.validate
                  : readDatasetCsv(request.validate_file, model.numJoints());
  held.gc = combinedProblem(request, &held.data, request.validate_file);
  if (request.validate == nullptr)
    held.noise = torqueNoiseOf(findPreparation(request.validate_file), held.data.meanRate(),
                               model.numJoints());
  // As the estimate's own held-out error: through the training torque's filter, if any.
  if (out.torque_filter.active() && out.filter_reach > 0) {
    Trajectory velocities;
    velocities.time = held.data.time;
    velocities.dq = held.data.dq;
    held.rows = trainingRows(model, velocities, out.torque_filter);
  }
  return held;
}

/// identify's front: combined at each of request.front_weights from pc, every point measured on
/// the held-out data, the estimate the one chooseByHeldOut takes. Returns the chosen point's
/// detail.
CombinedResult sweepFront(const IdentifyRequest& request, const Model& model, MethodRunner& runner,
                          const LeastSquaresSource& source, const GcProblem& train,
                          const HeldOut& held, IdentifyOutcome& out) {
  const LeastSquaresOutcome& pc = runner.leastSquares(Method::kPc);
  CombinedOptions options = request.combined;
  options.num_threads = runner.pool().numThreads();
  options.control.say("identify: the front, combined at " +
                      std::to_string(request.front_weights.size()) +
                      " GC weights, each from the last");
  const std::vector<FrontPoint> points =
      combinedFront(model, out.base, source, pc, train, options, request.front_weights);
  IdentifyFront front;
  front.tolerance = request.front_tolerance;
  GcWorkspace workspace(runner.pool().numThreads());
  std::vector<HeldOutErrors> errors;
  for (const FrontPoint& p : points) {
    IdentifyFrontPoint row;
    row.weight = p.weight;
    row.torque_train = p.estimate.estimate.relative_error;
    row.gc_train = p.detail.final_gc;
    row.test = held.errorsOf(model, p.estimate.standard, runner.pool(), workspace);
    row.iterations = p.detail.iterations;
    row.seconds = p.detail.seconds;
    row.note = combinedNote(p.detail);
    errors.push_back(row.test);
    front.points.push_back(std::move(row));
  }
  front.choice = chooseByHeldOut(errors, request.front_tolerance);
  if (front.choice.index < 0)
    throw NumericalError(request.validate_file +
                         ": no point of the front has finite held-out errors (its rollouts "
                         "diverge): no estimate to choose");
  out.result = points[front.choice.index].estimate;
  out.front = std::move(front);
  CombinedResult detail = points[out.front->choice.index].detail;
  detail.initial_gc = points.front().detail.initial_gc;  // pc's, as the summary compares with
  return detail;
}

/// The combined estimate's two criteria against pc's, on the training and held-out data.
CombinedSummary combinedSummary(const Model& model, const LeastSquaresOutcome& pc,
                                const CombinedResult& detail, const GcProblem& train,
                                const std::optional<HeldOut>& held, const IdentifyOutcome& out,
                                ThreadPool& pool) {
  CombinedSummary summary;
  summary.detail = detail;
  summary.train_segments = train.numSegments();
  summary.torque_train_pc = pc.estimate.relative_error;
  summary.gc_train_pc = detail.initial_gc;
  summary.gc_train = detail.final_gc;
  summary.gc_test_pc = summary.gc_test = std::numeric_limits<double>::quiet_NaN();
  summary.torque_test_pc = std::numeric_limits<double>::quiet_NaN();
  if (!held) return summary;
  summary.test_segments = held->gc.numSegments();
  GcWorkspace workspace(pool.numThreads());
  const HeldOutErrors at_pc = held->errorsOf(model, pc.standard, pool, workspace);
  summary.gc_test_pc = at_pc.gc;
  summary.torque_test_pc = at_pc.torque;
  Model identified = model;
  identified.setStandardParameters(out.result.standard);
  summary.gc_test = gcError(identified, held->gc, workspace, pool);
  return summary;
}

/// The least-squares problem of the training data, streamed (memory independent of its length).
EstimationProblem streamedProblem(const IdentifyRequest& request, const Model& model,
                                  const FitRows& rows, LeastSquaresStream& stream,
                                  const IdentifyOutcome& out, ThreadPool*& reader_pool) {
  const bool physical = takesPrior(request.method);
  EstimationProblem problem;
  problem.model = model;
  problem.base = &out.base;
  problem.least_squares.stream = &stream;
  problem.least_squares.layout = model.parameterLayout();
  problem.least_squares.rows = &rows;
  problem.prior =
      physical && request.prior ? request.prior->standardParameters() : model.standardParameters();
  problem.physical.prior_weight = request.prior_weight;
  problem.combined = request.combined;
  problem.control = request.combined.control;
  problem.threads = resolveThreads(request.threads);
  problem.covariance = request.covariance;
  // The covariance's pass: the training data again, in the same chunks.
  if (request.data) {
    const Trajectory* data = request.data;
    problem.least_squares.replay = [data](const std::function<void(const Trajectory&)>& each) {
      each(*data);
    };
  } else {
    problem.least_squares.replay = [&request, &reader_pool, n = model.numJoints()](
                                       const std::function<void(const Trajectory&)>& each) {
      DatasetReader reader(request.data_file, n);
      Trajectory chunk;
      while (reader.read(chunk, kStreamChunkSamples, reader_pool) > 0) each(chunk);
    };
  }
  return problem;
}

/// The estimate of request.method through the estimation wing's runner, streaming the training
/// data and keeping samples for the figures; with combined, its two criteria against pc's on the
/// training and held-out data (and with front_weights, the front it was chosen from).
void estimate(const IdentifyRequest& request, const Model& model, const FitRows& rows,
              IdentifyOutcome& out, SampleKeeper& kept) {
  LeastSquaresStream stream(out.base, model);
  ThreadPool* reader_pool = nullptr;  // the runner's, once it exists
  EstimationProblem problem = streamedProblem(request, model, rows, stream, out, reader_pool);
  std::optional<GcProblem> train;
  if (request.method == Method::kCombined) {
    train.emplace(combinedProblem(request, request.data, request.data_file));
    problem.train_gc = &*train;
  }
  const LeastSquaresSource source = problem.least_squares;
  MethodRunner runner(std::move(problem));
  reader_pool = &runner.pool();
  if (request.data) {
    stream.addTrajectory(model, *request.data, &runner.pool(), &rows);
    kept.add(*request.data);
  } else {
    addDatasetFile(stream, model, request.data_file, runner.pool(), &kept, kStreamChunkSamples,
                   &rows);
  }
  if (request.method != Method::kCombined) {
    out.result = *runner.run(request.method).least_squares;
    return;
  }
  const std::optional<HeldOut> held = heldOutOf(request, model, out);
  CombinedResult detail;
  if (request.front_weights.empty()) {
    out.result = *runner.run(Method::kCombined).least_squares;
    detail = *runner.combinedDetail();
  } else {
    detail = sweepFront(request, model, runner, source, *train, *held, out);
  }
  out.combined = combinedSummary(model, runner.leastSquares(Method::kPc), detail, *train, held, out,
                                 runner.pool());
}

/// The fit's statistics (the estimate's residuals, from the stream's factors) on the kept training
/// samples as the fit took them (the friction columns through the torque's filter), and where the
/// residual of the rows it fitted lies in velocity.
void describeFit(const Model& identified, const SampleKeeper& kept, const FitRows& rows,
                 IdentifyOutcome& out) {
  const BaseEstimate& e = out.result.estimate;
  Validation v;
  v.num_samples = e.num_samples;
  v.torque_rms = e.residual_rms;
  v.normalised_rms = e.joint_relative_error;
  v.relative_error = e.relative_error;
  out.fit = predictionOfKept(identified, kept, v, e.measured_rms);
  addFilteredFriction(identified, rows, out.fit);
  const ReversalMask fitted = fittedMask(out.fit, rows);
  out.reversals = reversalResidual(out.fit, &fitted);
}

/// The held-out data's samples through the training torque's filter (when the fit reproduced
/// one): the held-out torque went through it too.
std::optional<FitRows> heldOutRows(const IdentifyRequest& request, const Model& identified,
                                   const IdentifyOutcome& out) {
  if (!out.torque_filter.active() || out.filter_reach == 0) return std::nullopt;
  const int n = identified.numJoints();
  Trajectory velocities;
  if (request.validate != nullptr) {
    velocities.time = request.validate->time;
    velocities.dq = request.validate->dq;
  } else {
    velocities = velocitiesOf(request.validate_file, n);
  }
  try {
    return trainingRows(identified, velocities, out.torque_filter);
  } catch (const InputError& e) {
    throw InputError(request.validate_file + ": " + e.what());
  }
}

/// The held-out prediction, and against the raw held-out torques when given.
void validate(const IdentifyRequest& request, const Model& identified, IdentifyOutcome& out) {
  if (!request.validate && request.validate_file.empty()) {
    if (!request.validate_raw_file.empty())
      throw InputError("the raw held-out torques (" + request.validate_raw_file +
                       ") need the held-out dataset they belong to (validate)");
    return;
  }
  std::optional<RawTorques> raw;
  std::optional<RawTorqueComparison> comparison;
  if (!request.validate_raw_file.empty()) {
    raw = readRawTorques(request.validate_raw_file, identified.numJoints());
    comparison.emplace(*raw);
  }
  PredictionSink* sink = comparison ? &*comparison : nullptr;
  ThreadPool pool(request.threads);
  const std::optional<FitRows> rows = heldOutRows(request, identified, out);
  const FitRows* filtered = rows ? &*rows : nullptr;
  out.validate_fit = request.validate ? predictTorques(identified, *request.validate, &pool, sink,
                                                       nullptr, filtered)
                                      : predictFile(identified, request.validate_file, pool, sink,
                                                    kStreamChunkSamples, nullptr, filtered);
  out.validation = out.validate_fit->validation;
  out.validate_file = request.validate_file;
  if (comparison) {
    out.raw_validation = comparison->result();
    out.validate_raw_file = request.validate_raw_file;
    out.raw_skipped = comparison->skipped();
  }
}

/// The estimate written back into the robot's URDF and as dynid JSON; refused for an estimate that
/// is not physically consistent.
WriteBack writeBack(const IdentifyRequest& request, const Model& identified,
                    const IdentifyOutcome& out) {
  if (!out.violations.empty())
    throw InputError("cannot write the " + std::string(methodName(request.method)) +
                     " estimate back: link '" + out.violations.front().link_name +
                     "' is not physically consistent (" + out.violations.front().condition +
                     "); use `method` pc");
  return estimateWriteBack(request.write_back_from, identified,
                           out.base.numStandard() - out.base.numBase());
}

/// What follows an estimate: the consistency check, the fit's statistics, the held-out
/// validation and the write-back.
void finishIdentify(const IdentifyRequest& request, const Model& model, const FitRows& rows,
                    const SampleKeeper& kept, IdentifyOutcome& out) {
  if (out.result.pc)
    for (int i : out.result.pc->inconsistent_links)
      out.pc_inconsistent_links.push_back(model.link_names[i]);
  Model identified = model;
  identified.setStandardParameters(out.result.standard);
  out.violations = consistencyViolations(identified);
  describeFit(identified, kept, rows, out);
  validate(request, identified, out);
  if (!request.write_back_from.empty()) out.write_back = writeBack(request, identified, out);
}

/// The estimate from a summary (request.summary): its rows through the runner, its batches for the
/// covariance.
IdentifyOutcome identifyFromSummary(const IdentifyRequest& request) {
  const Summary& summary = *request.summary;
  const std::string& name = request.summary_name;
  if (request.method == Method::kCombined)
    throw InputError(name +
                     ": `method` combined rolls the model out over the samples, which a "
                     "summary does not hold: give the logs (`data`)");
  if (const std::string why = kinematicsDifference(summary.model, request.model, name + "'s robot");
      !why.empty() || summary.model.driveTerms().mask != request.model.driveTerms().mask)
    throw InputError(name + " was made for another robot than `model`" +
                     (why.empty() ? ": its drive terms differ" : ": " + why));
  IdentifyOutcome out;
  out.method = request.method;
  out.prior_weight = request.prior_weight;
  out.data_file = name;
  out.robot_spec = request.robot_spec;
  out.summary_sources = summary.sources;
  // The logs' torque filter, when they share one: the held-out prediction reproduces it.
  out.torque_filter_source = "each log's own, as its summary records";
  const auto same_filter = [&](const SummarySource& s) {
    const TorqueFilter& f = summary.sources.front().torque_filter;
    return s.torque_filter.order == f.order && s.torque_filter.cutoff == f.cutoff &&
           std::abs(s.torque_filter.rate - f.rate) <= 1e-6 * f.rate;
  };
  if (!summary.sources.empty() && summary.sources.front().torque_filter.active() &&
      std::all_of(summary.sources.begin(), summary.sources.end(), same_filter)) {
    out.torque_filter = summary.sources.front().torque_filter;
    out.filter_reach = filterReach(out.torque_filter);
    out.torque_filter_source = "the summaries' logs' (each its own rows)";
  }
  // The rest velocities: per joint the largest of the logs' (a joint at rest in any log is at
  // rest below it), for the held-out prediction.
  Model model = request.model;
  model.rest_velocities.assign(static_cast<std::size_t>(model.numJoints()), 0.0);
  for (const SummarySource& source : summary.sources)
    for (std::size_t j = 0; j < source.rest_velocity.size(); ++j)
      model.rest_velocities[j] = std::max(model.rest_velocities[j], source.rest_velocity[j]);
  out.base = summaryBase(summary, name);
  out.model_beta = out.base.project(model.standardParameters());
  LeastSquaresStream stream(out.base, model);
  summary.factors.addTo(stream);
  EstimationProblem problem;
  problem.model = model;
  problem.base = &out.base;
  problem.least_squares.stream = &stream;
  problem.least_squares.layout = model.parameterLayout();
  problem.least_squares.summary = &summary.factors;
  problem.prior = takesPrior(request.method) && request.prior ? request.prior->standardParameters()
                                                              : model.standardParameters();
  problem.physical.prior_weight = request.prior_weight;
  problem.control = request.combined.control;
  problem.threads = resolveThreads(request.threads);
  problem.covariance = request.covariance;
  MethodRunner runner(std::move(problem));
  try {
    out.result = *runner.run(request.method).least_squares;
  } catch (const InputError& e) {
    throw InputError(name + ": " + e.what());
  } catch (const NumericalError& e) {
    throw NumericalError(name + ": " + e.what());
  }
  finishIdentify(request, model, FitRows(model), SampleKeeper(), out);
  return out;
}

}  // namespace

WriteBack estimateWriteBack(const std::string& urdf_file, const Model& identified,
                            int unseen_directions) {
  WriteBack back;
  back.urdf = urdfWithParameters(readFile(urdf_file), urdf_file, identified);
  back.model_json = modelToJson(identified);
  back.unseen_directions = unseen_directions;
  for (const DriveTermInfo& row : kDriveTermTable)
    if (row.urdf_dynamics.empty() && identified.driveTerms().has(row.term))
      for (int j = 0; j < identified.numJoints(); ++j)
        if (const double value = identified.drives()[j][row.term]; value != 0.0)
          back.not_in_urdf.push_back(std::string(row.name) + std::to_string(j + 1) + " " +
                                     formatNumber(value, 4) + " " + std::string(row.unit));
  return back;
}

IdentifyOutcome identifyRun(const IdentifyRequest& request) {
  request.check();
  if (request.summary != nullptr) return identifyFromSummary(request);
  IdentifyOutcome out;
  TrainingSet training = trainingSetOf(request.model, request.data_file, request.data,
                                       request.rest_velocity, request.torque_filter);
  out.preparation = std::move(training.preparation);
  out.torque_filter = training.torque_filter;
  out.torque_filter_source = std::move(training.torque_filter_source);
  out.filter_reach = training.filter_reach;
  out.rest = std::move(training.rest);
  const Model& model = training.model;
  const FitRows& rows = training.rows;
  out.method = request.method;
  out.prior_weight = request.prior_weight;
  out.data_file = request.data_file;
  out.robot_spec = request.robot_spec;
  std::error_code error;
  if (!request.robot_spec.empty() && std::filesystem::is_regular_file(request.robot_spec, error))
    out.robot_sha256 = sha256OfFile(request.robot_spec);
  out.base = structuralBaseParameters(model, request.structural);
  out.model_beta = out.base.project(model.standardParameters());
  if (request.prior && request.prior->parameterLayout().size() != model.parameterLayout().size())
    throw InputError("the prior model has another parameter layout than the robot");
  SampleKeeper kept;  // the training samples for the figures
  try {
    estimate(request, model, rows, out, kept);
  } catch (const InputError& e) {  // too few samples: the dataset's fault
    throw InputError(request.data_file + ": " + e.what());
  } catch (const NumericalError& e) {  // unexcited parameters: the dataset's too
    throw NumericalError(request.data_file + ": " + e.what());
  }
  finishIdentify(request, model, rows, kept, out);
  return out;
}

}  // namespace dynid
