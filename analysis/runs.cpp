#include "analysis/runs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <random>
#include <thread>

#include <Eigen/SVD>

#include "analysis/excitation/excite.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/records/excitation_record.hpp"
#include "analysis/records/search_record.hpp"
#include "core/aba.hpp"
#include "core/controllers.hpp"
#include "core/crba.hpp"
#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/kinematics.hpp"
#include "core/perturb.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"
#include "data/urdf_writeback.hpp"
#include "identifiability/least_squares_stream.hpp"

namespace dynid {

int resolveThreads(int threads) {
  return threads > 0 ? threads
                     : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// ---- models and dynamics ----

std::vector<Pose<double>> linkFramesAtZero(const Model& model) {
  Data data(model);
  return forwardKinematics(model, data, Eigen::VectorXd::Zero(model.numJoints()));
}

std::vector<ConsistencyViolation> consistencyViolations(const Model& model) {
  std::vector<ConsistencyViolation> all;
  for (int i = 0; i < model.numJoints(); ++i) {
    auto v = checkPhysicalConsistency(model.inertias()[i], i, model.link_names[i]);
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

DynamicsOutcome dynamicsAt(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                           const std::optional<Eigen::VectorXd>& ddq,
                           const std::optional<Eigen::VectorXd>& tau) {
  const int n = model.numJoints();
  Data data(model);
  DynamicsOutcome out{q, dq, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), {}};
  // With tau: ddq = ABA(q, dq, tau), and tau is echoed; otherwise tau = RNEA(q, dq, ddq).
  if (tau) {
    out.tau = *tau;
    out.ddq = aba(model, data, q, dq, *tau);
  } else {
    if (ddq) out.ddq = *ddq;
    out.tau = rnea(model, data, q, dq, out.ddq);
  }
  out.M = crba(model, data, q);
  if (!out.ddq.allFinite() || !out.tau.allFinite() || !out.M.allFinite())
    throw NumericalError("the dynamics of '" + model.name +
                         "' are singular at this state: the mass matrix is not positive definite "
                         "(is a moving subtree massless?)");
  return out;
}

// ---- simulation ----

FourierSeries randomFourier(const Eigen::VectorXd& q0, const Eigen::VectorXd& amplitude,
                            double base_frequency, int harmonics, std::uint64_t seed) {
  FourierSeries r;
  r.offset = q0;
  r.period = 1.0 / base_frequency;
  const int n = static_cast<int>(q0.size());
  r.a.resize(n, harmonics);
  r.b.resize(n, harmonics);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double w = 2.0 * std::numbers::pi * base_frequency;
  for (int i = 0; i < n; ++i) {
    double bound = 0.0;
    for (int k = 0; k < harmonics; ++k) {
      r.a(i, k) = uniform(rng);
      r.b(i, k) = uniform(rng);
      bound += (std::abs(r.a(i, k)) + std::abs(r.b(i, k))) / (w * (k + 1));
    }
    const double scale = bound > 0.0 ? amplitude[i] / bound : 0.0;
    r.a.row(i) *= scale;
    r.b.row(i) *= scale;
  }
  return r;
}

SimulateOutcome simulateRun(const SimulateRequest& request) {
  if (request.one_period && !request.trajectory.empty()) {
    // The duration is the design's period, checked (memory included) as a given one would be.
    SimulateRequest resolved = request;
    resolved.simulation.duration =
        readExcitationDesign(request.trajectory, request.robot.numJoints()).period;
    resolved.one_period = false;
    return simulateRun(resolved);
  }
  request.check();
  const Model& truth = request.robot;
  const int n = truth.numJoints();
  // The controller's own model: another robot, or the truth, optionally perturbed.
  Model controller_model = request.controller_model.value_or(truth);
  if (controller_model.numJoints() != n)
    throw InputError("the controller's robot has " + std::to_string(controller_model.numJoints()) +
                     " joints, the robot has " + std::to_string(n));
  if (request.controller_perturb != 0.0)
    controller_model =
        perturbedModel(controller_model, request.controller_perturb, request.simulation.seed);

  Eigen::VectorXd q0 = request.q0.value_or(defaultCentre(truth));
  Reference reference;
  if (!request.trajectory.empty()) {
    const FourierSeries design = readExcitationDesign(request.trajectory, n);
    reference = design;
    q0 = design.offset;  // the default gains' configuration
  } else if (!request.fourier) {
    SinusoidalReference r;
    r.q0 = q0;
    r.amplitude = request.amplitude;
    r.frequency = request.frequency.value_or(defaultFrequencies(n));
    r.phase = request.phase.value_or(Eigen::VectorXd::Zero(n));
    reference = r;
  } else {
    reference = randomFourier(q0, request.amplitude, request.base_frequency, request.harmonics,
                              request.simulation.seed);
  }
  SimulateOutcome out;
  TrackingGains gains = defaultGains(controller_model, q0, request.bandwidth);
  out.gains_rule = "mass-matrix diagonal";
  // The paper's diagonal gains, unless the joints' coupling puts a closed-loop mode above 3 times
  // the bandwidth (the Panda's aligned axes at rest: its 1 kHz loop then chatters between the
  // torque limits); the effective inertias' gains keep every mode within sqrt(n) times it.
  if (!request.kp && !request.kd &&
      closedLoopFrequency(controller_model, q0, gains.kp) > 3.0 * request.bandwidth) {
    gains = effectiveInertiaGains(controller_model, q0, request.bandwidth);
    out.gains_rule = "effective inertia";
  }
  if (request.kp) gains.kp = *request.kp;
  if (request.kd) gains.kd = *request.kd;
  if (request.kp || request.kd) out.gains_rule = "given";
  Eigen::VectorXd tau_max(n);
  for (int i = 0; i < n; ++i) tau_max[i] = truth.limits[i].effort;
  if (request.tau_max) tau_max = *request.tau_max;

  TrackingController controller(controller_model, reference, gains, tau_max);
  out.trajectory = simulate(truth, controller, request.simulation, request.disturbances,
                            request.disturbances.empty() ? nullptr : &out.external);
  // Tracking error RMS and peak torque.
  const Trajectory& t = out.trajectory;
  Eigen::VectorXd q_des, dq_des, ddq_des;
  double squared_error = 0.0;
  for (int k = 0; k < t.numSamples(); ++k) {
    evaluateReference(reference, t.time[k], q_des, dq_des, ddq_des);
    squared_error += (t.q.col(k) - q_des).squaredNorm();
  }
  out.tracking_rms = std::sqrt(squared_error / (static_cast<double>(t.numSamples()) * n));
  out.peak_torque = t.tau.cwiseAbs().maxCoeff();
  int saturated = 0;
  for (int k = 0; k < t.numSamples(); ++k) {
    if (k > 0)
      out.max_torque_step =
          std::max(out.max_torque_step, (t.tau.col(k) - t.tau.col(k - 1)).cwiseAbs().maxCoeff());
    // At the limit to within 1e-9 relative: the controller's saturation writes the limit itself.
    bool at_limit = false;
    for (int i = 0; i < n; ++i)
      at_limit = at_limit ||
                 (std::isfinite(tau_max[i]) && std::abs(t.tau(i, k)) >= tau_max[i] * (1.0 - 1e-9));
    saturated += at_limit;
  }
  out.saturated_share = t.numSamples() > 0 ? static_cast<double>(saturated) / t.numSamples() : 0.0;
  return out;
}

// ---- identifiability ----

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
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(f.r_scaled).singularValues();
    const bool full = stream.numSamples() * model.numJoints() >= out.base.numBase() &&
                      f.norms.minCoeff() > 0.0 && s.size() > 0 && s[s.size() - 1] > 0.0;
    out.data =
        DataExcitation{data_file, stream.numSamples(), excitationFromRDiagonal(r_diagonal),
                       full ? s[0] / s[s.size() - 1] : std::numeric_limits<double>::infinity()};
  }
  return out;
}

// ---- identification ----

namespace {

/// identify's combined step: pc's outcome (`result`, replaced by the combined estimate's) refined
/// on the training data's GC residuals, and both criteria measured for pc and the estimate.
CombinedSummary combinedStep(const IdentifyRequest& request, const BaseParameters& base,
                             const LeastSquaresSource& source, LeastSquaresOutcome& result,
                             ThreadPool& pool) {
  const Model& model = request.model;
  const int n = model.numJoints();
  const auto problemOf = [&](const Trajectory* given, const std::string& file) {
    try {
      return makeGcProblemUpTo(given != nullptr ? *given : readDatasetCsv(file, n),
                               request.segments);
    } catch (const InputError& e) {
      throw InputError(file + ": " + e.what());
    }
  };
  const GcProblem train = problemOf(request.data, request.data_file);
  CombinedSummary out;
  out.train_segments = train.numSegments();
  Model pc_model = model;
  pc_model.setStandardParameters(result.standard);
  out.torque_train_pc = result.estimate.relative_error;
  CombinedOptions options = request.combined;
  options.num_threads = pool.numThreads();
  result = combinedEstimate(model, base, source, result, train, options, &out.detail);
  out.gc_train_pc = out.detail.initial_gc;
  out.gc_train = out.detail.final_gc;
  out.gc_test_pc = out.gc_test = std::numeric_limits<double>::quiet_NaN();
  out.torque_test_pc = std::numeric_limits<double>::quiet_NaN();
  if (request.validate != nullptr || !request.validate_file.empty()) {
    const Trajectory held =
        request.validate != nullptr ? *request.validate : readDatasetCsv(request.validate_file, n);
    const GcProblem test = problemOf(&held, request.validate_file);
    out.test_segments = test.numSegments();
    GcWorkspace workspace(pool.numThreads());
    Model identified = model;
    identified.setStandardParameters(result.standard);
    out.gc_test_pc = gcError(pc_model, test, workspace, pool);
    out.gc_test = gcError(identified, test, workspace, pool);
    out.torque_test_pc = predictTorques(pc_model, held, &pool).validation.relative_error;
  }
  return out;
}

}  // namespace

IdentifyOutcome identifyRun(const IdentifyRequest& request) {
  request.check();
  const Model& model = request.model;
  IdentifyOutcome out;
  out.method = request.method;
  out.prior_weight = request.prior_weight;
  out.data_file = request.data_file;
  out.base = structuralBaseParameters(model, request.structural);
  out.model_beta = out.base.project(model.standardParameters());
  if (request.prior && request.prior->parameterLayout().size() != model.parameterLayout().size())
    throw InputError("the prior model has another parameter layout than the robot");
  const bool physical = request.method == Method::kPc || request.method == Method::kCombined;
  const Eigen::VectorXd prior =
      physical && request.prior ? request.prior->standardParameters() : model.standardParameters();
  PhysicalOptions pc_options;
  pc_options.prior_weight = request.prior_weight;
  ThreadPool pool(request.threads);
  SampleKeeper kept;  // the training samples for the figures
  try {
    // Every method streams the file: memory independent of the dataset's length.
    LeastSquaresStream stream(out.base, model);
    if (request.data) {
      stream.addTrajectory(model, *request.data, &pool);
      kept.add(*request.data);
    } else {
      addDatasetFile(stream, model, request.data_file, pool, &kept);
    }
    const LeastSquaresSource source{nullptr, &stream, model.parameterLayout()};
    out.result =
        leastSquaresEstimate(request.method == Method::kCombined ? Method::kPc : request.method,
                             out.base, source, prior, pc_options);
    if (request.method == Method::kCombined)
      out.combined = combinedStep(request, out.base, source, out.result, pool);
  } catch (const InputError& e) {  // too few samples: the dataset's fault
    throw InputError(request.data_file + ": " + e.what());
  } catch (const NumericalError& e) {  // unexcited parameters: the dataset's too
    throw NumericalError(request.data_file + ": " + e.what());
  }
  if (out.result.pc)
    for (int i : out.result.pc->inconsistent_links)
      out.pc_inconsistent_links.push_back(model.link_names[i]);
  out.robot_spec = request.robot_spec;
  Model identified = model;
  identified.setStandardParameters(out.result.standard);
  out.violations = consistencyViolations(identified);
  {  // the fit's statistics are the estimate's residuals', from the stream's factors
    const BaseEstimate& e = out.result.estimate;
    Validation v;
    v.num_samples = e.num_samples;
    v.torque_rms = e.residual_rms;
    v.normalised_rms = e.joint_relative_error;
    v.relative_error = e.relative_error;
    out.fit = predictionOfKept(identified, kept, v, e.measured_rms);
    out.reversals = reversalResidual(out.fit);
  }
  if (!request.data) out.preparation = findPreparation(request.data_file);
  if (request.validate || !request.validate_file.empty()) {
    std::optional<RawTorques> raw;
    std::optional<RawTorqueComparison> comparison;
    if (!request.validate_raw_file.empty()) {
      raw = readRawTorques(request.validate_raw_file, identified.numJoints());
      comparison.emplace(*raw);
    }
    PredictionSink* sink = comparison ? &*comparison : nullptr;
    out.validate_fit = request.validate
                           ? predictTorques(identified, *request.validate, &pool, sink)
                           : predictFile(identified, request.validate_file, pool, sink);
    out.validation = out.validate_fit->validation;
    out.validate_file = request.validate_file;
    if (comparison) {
      out.raw_validation = comparison->result();
      out.validate_raw_file = request.validate_raw_file;
      out.raw_skipped = comparison->skipped();
    }
  } else if (!request.validate_raw_file.empty()) {
    throw InputError("the raw held-out torques (" + request.validate_raw_file +
                     ") need the held-out dataset they belong to (validate)");
  }
  if (!request.write_back_from.empty()) {
    if (!out.violations.empty())
      throw InputError("cannot write the " + std::string(methodName(request.method)) +
                       " estimate back: link '" + out.violations.front().link_name +
                       "' is not physically consistent (" + out.violations.front().condition +
                       "); use --method pc");
    WriteBack back;
    back.urdf =
        urdfWithParameters(readFile(request.write_back_from), request.write_back_from, identified);
    back.model_json = modelToJson(identified);
    back.unseen_directions = out.base.numStandard() - out.base.numBase();
    for (const DriveTermInfo& row : kDriveTermTable)
      if (row.urdf_dynamics.empty() && identified.driveTerms().has(row.term))
        for (int j = 0; j < identified.numJoints(); ++j)
          if (const double value = identified.drives()[j][row.term]; value != 0.0)
            back.not_in_urdf.push_back(std::string(row.name) + std::to_string(j + 1) + " " +
                                       formatNumber(value, 4) + " " + std::string(row.unit));
    out.write_back = std::move(back);
  }
  return out;
}

// ---- applying an estimate to data ----

Eigen::MatrixXd kinematicsSignature(const Model& model) {
  const std::vector<Pose<double>> frames = linkFramesAtZero(model);
  Eigen::MatrixXd out(model.numJoints(), 15);
  for (int i = 0; i < model.numJoints(); ++i) {
    const Eigen::Matrix3d& r = frames[i].rotation;
    // The axis is given in the joint frame; the link frame is the joint frame times the body
    // placement, so the axis in the base frame is R_link R_body^T axis.
    const Eigen::Vector3d axis =
        r * model.body_placements()[i].rotation.transpose() * model.axes()[i];
    out.row(i) << r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2),
        frames[i].translation.transpose(), axis.transpose();
  }
  return out;
}

Model estimateModel(const std::string& file, const std::string& robot_spec, std::string* spec_used,
                    std::string* method, std::optional<PredictionBand>* band) {
  const EstimateRecord estimate = estimateRecordFrom(parseJson(readFile(file), file), file);
  const std::string spec = robot_spec.empty() ? estimate.robot_spec : robot_spec;
  if (spec.empty())
    throw ParseError(file, 0, "robot_spec",
                     "the estimate does not say which robot it is for: give --robot");
  if (spec_used != nullptr) *spec_used = spec;
  if (method != nullptr) *method = estimate.method;
  std::string terms;
  for (const std::string& t : estimate.drive_terms) terms += (terms.empty() ? "" : ",") + t;
  RobotOptions options;
  try {
    options.drive_terms = parseDriveTerms(terms.empty() ? "none" : terms);
  } catch (const InputError& e) {
    throw ParseError(file, 0, "drive_terms", e.what());
  }
  Model model;
  if (robot_spec.empty()) {
    try {  // the robot the estimate names: a failure names the estimate and its field
      model = loadRobot(spec, options);
    } catch (const Error& e) {
      throw ParseError(file, 0, "robot_spec", std::string("cannot load its robot: ") + e.what());
    }
  } else {
    model = loadRobot(spec, options);
  }
  model.setStandardParameters(
      standardVectorFrom(estimate, standardParameterNames(model.parameterLayout()), file, spec));
  // Same parameter names on other kinematics (a standard-DH robot and its URDF, whose link frames
  // differ) would give wrong torques silently: compare the recorded kinematics.
  if (!estimate.kinematics.is_null()) {
    const Eigen::MatrixXd mine = kinematicsSignature(model);
    const nlohmann::json& recorded = estimate.kinematics;
    bool same = recorded.size() == static_cast<std::size_t>(mine.rows());
    for (Eigen::Index i = 0; same && i < mine.rows(); ++i)
      for (Eigen::Index c = 0; same && c < 15; ++c)
        same = recorded[i][c].is_number() &&
               std::abs(recorded[i][c].get<double>() - mine(i, c)) <= 1e-9;
    if (!same)
      throw InputError(file + ": robot '" + spec +
                       "' has other link frames or axes than the robot the estimate was made for: "
                       "it was made for another robot");
  }
  if (band && !estimate.band_columns.empty()) {
    const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
    PredictionBand b;
    for (std::size_t c = 0; c < estimate.band_columns.size(); ++c) {
      const auto it = std::find(names.begin(), names.end(), estimate.band_columns[c]);
      if (it == names.end())
        throw ParseError(file, 0, JsonReader::index("base_covariance.columns", c),
                         "'" + estimate.band_columns[c] + "' is not a parameter of the robot");
      b.independent.push_back(static_cast<int>(it - names.begin()));
    }
    b.covariance = estimate.covariance;
    if (estimate.joint_sigma.size() != model.numJoints())
      throw ParseError(file, 0, "joint_sigma",
                       "expected " + std::to_string(model.numJoints()) +
                           " numbers with the "
                           "base covariance");
    b.noise_sigma = estimate.joint_sigma;
    *band = std::move(b);
  }
  return model;
}

PredictOutcome predictRun(const PredictRequest& request) {
  PredictOutcome out;
  if (request.estimate_file.empty() == !request.model)
    throw InputError("predict needs an estimate.json or a robot model (one of them)");
  if (request.model) {
    out.model = *request.model;
    out.robot_spec = request.robot_spec;
    out.method = "model";
  } else {
    out.model = estimateModel(request.estimate_file, request.robot_spec, &out.robot_spec,
                              &out.method, &out.band);
  }
  const PredictionBand* band = out.band ? &*out.band : nullptr;
  ThreadPool pool(request.threads);
  if (request.raw_file.empty()) {
    out.prediction =
        predictFile(out.model, request.data_file, pool, request.sink, kStreamChunkSamples, band);
    out.reversals = reversalResidual(out.prediction);
    return out;
  }
  const RawTorques raw = readRawTorques(request.raw_file, out.model.numJoints());
  RawTorqueComparison comparison(raw, request.sink);
  out.prediction =
      predictFile(out.model, request.data_file, pool, &comparison, kStreamChunkSamples, band);
  out.reversals = reversalResidual(out.prediction);
  out.raw = comparison.result();
  out.raw_file = request.raw_file;
  out.raw_skipped = comparison.skipped();
  return out;
}

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

RefineOutcome refineRun(const RefineRequest& request) {
  request.check();
  const Model& robot = request.robot;
  RefineOutcome out;
  out.robot = robot.name;
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

LoadedArm loadArm(const std::string& arm, const std::string& robot_spec,
                  const std::optional<DriveTerms>& drive_terms,
                  std::vector<std::string>* warnings) {
  LoadedArm out;
  std::error_code error;
  if (std::filesystem::path(arm).extension() == ".json" &&
      std::filesystem::is_regular_file(arm, error)) {
    const nlohmann::json document = parseJson(readFile(arm), arm);
    if (document.is_object() && document.contains("kind") && document["kind"].is_string() &&
        document["kind"].get<std::string>() == kEstimateDocument.kind) {
      if (drive_terms)
        throw InputError(arm + ": an estimate carries its own drive terms; drop --drive-terms");
      out.model = estimateModel(arm, robot_spec, &out.robot_spec, nullptr);
      out.from_estimate = true;
      const EstimateRecord record = estimateRecordFrom(document, arm);
      out.torque_constants = record.torque_constants;
      out.gear_ratios = record.gear_ratios;
      return out;
    }
  }
  if (!robot_spec.empty())
    throw InputError("--robot applies to an estimate.json arm; '" + arm + "' is a robot itself");
  RobotOptions options;
  options.drive_terms = drive_terms;
  out.model = loadRobot(arm, options, warnings);
  out.robot_spec = arm;
  return out;
}

}  // namespace dynid
