#include "analysis/studies/study.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "analysis/records/excitation_record.hpp"
#include "analysis/runs/simulate.hpp"
#include "core/controllers.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/perturb.hpp"
#include "core/simulate.hpp"
#include "data/robots.hpp"
#include "search/refinement/gc_jacobian.hpp"
#include "search/refinement/refine.hpp"

namespace dynid {

namespace {

/// The default sinusoidal tracking run of `dynid simulate` (train) or the held-out control path
/// of docs/SEARCH.md's default scenario (test), with the setting's noise.
Trajectory simulateRun(const Model& truth, const StudySettings& s, bool held_out) {
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
  Reference reference = r;
  Eigen::VectorXd centre = r.q0;
  if (!held_out && !s.trajectory.empty()) {  // a designed training motion
    const FourierSeries design = readExcitationDesign(s.trajectory, n);
    reference = design;
    centre = design.offset;
  }
  TrackingController controller(truth, reference, defaultGains(truth, centre, 5.0), tau_max);
  SimulationOptions options;
  options.duration = held_out ? s.test_seconds : s.train_seconds;
  options.noise_q = s.noise_q;
  options.noise_dq = s.noise_dq;
  options.noise_tau = s.noise_tau;
  options.seed = held_out ? s.seed + 1000 : s.seed;
  return simulate(truth, controller, options);
}

}  // namespace

void StudySettings::check() const {
  // The ranges of the one option table (core/option_ranges.hpp), under the manifest's names.
  checkOption("batch", "duration", train_seconds, "train_seconds");
  checkOption("batch", "duration", test_seconds, "test_seconds");
  checkOption("batch", "noise-q", noise_q, "noise_q");
  checkOption("batch", "noise-dq", noise_dq, "noise_dq");
  checkOption("batch", "noise-tau", noise_tau, "noise_tau");
  checkOption("batch", "segments", segments, "segments");  // 0: every segment
  checkOption("batch", "horizon", horizon, "horizon");
  checkOption("batch", "perturb", perturb, "perturb");
  checkOption("batch", "search-seconds", search_seconds, "search_seconds");
  checkOption("batch", "search-evaluations", static_cast<double>(search_evaluations),
              "search_evaluations");
  checkOption("study", "refine-iterations", refine_iterations, "refine_iterations");
  checkOption("batch", "refine-seconds", refine_seconds, "refine_seconds");
  checkOption("batch", "refine-tolerance", refine_tolerance, "refine_tolerance");
  checkOption("batch", "prior-weight", prior_weight, "prior_weight");
  if (!(search_seconds > 0.0 || search_evaluations > 0))
    throw InputError("search_seconds or search_evaluations must be > 0: a search needs a budget");
  if (threads < 1) throw InputError("threads must be >= 1");
}

Study::Study(const StudySettings& settings, RunControl control)
    : settings_(settings), control_(std::move(control)) {
  const auto say = [&](const std::string& line) { control_.say(line); };
  settings_.check();
  truth_ = loadRobot(settings_.robot);
  initial_ = perturbedModel(truth_, settings_.perturb, settings_.seed);
  say("simulating " + formatNumber(settings_.train_seconds) + " s of training and " +
      formatNumber(settings_.test_seconds) + " s of held-out data");
  train_data_ = simulateRun(truth_, settings_, false);
  test_data_ = simulateRun(truth_, settings_, true);
  SegmentOptions segments;
  segments.horizon = settings_.horizon;
  segments.num_segments = settings_.segments;
  train_ = makeGcProblem(train_data_, segments);
  test_ = makeGcProblem(test_data_, segments);

  say("base parameters");
  base_ = structuralBaseParameters(truth_);
  observation_ = observationFromTrajectory(truth_, train_data_);

  // Every estimate comes from the one pipeline: least squares with the initial guess as prior,
  // the searches from the initial guess (NLO on the true total mass), refinement of their results.
  EstimationProblem problem;
  problem.model = truth_;
  problem.base = &base_;
  problem.least_squares.observation = &observation_;
  problem.prior = initial_.standardParameters();
  problem.physical.prior_weight = settings_.prior_weight;
  problem.train_gc = &train_;
  problem.start = initial_;
  problem.total_mass = totalMass(truth_);
  problem.seed = settings_.seed;
  // combined (a batch's method) with the refinements' iterations and seconds, as dynid study
  // gives it on logs; its own convergence tolerance.
  problem.setBudgets(settings_.search_seconds, settings_.search_evaluations,
                     settings_.refine_iterations, settings_.refine_seconds,
                     settings_.refine_tolerance, settings_.keep_if_better);
  problem.truth_full = &truth_full_;
  problem.on_search_iteration = [this](Method method, const SearchState& state,
                                       const ParameterSpace& space) {
    search_base_errors_[method].push_back(
        baseParameterError(base_.project(space.standardAt(state.best_x)), beta_true_));
  };
  problem.threads = settings_.threads;
  problem.control = control_;
  runner_ = std::make_unique<MethodRunner>(std::move(problem));
  const ParameterSpace& ga_space = runner_->space(Method::kGa);
  comparison_ = std::make_unique<Comparison>(truth_, ga_space, base_, train_, test_, test_data_,
                                             runner_->pool());
  initial_gc_ = comparison_->trainGc(initial_);
  initial_test_gc_ = comparison_->testGc(initial_);
  truth_full_ = ga_space.fullVector(truth_);
  beta_true_ = base_.project(truth_.standardParameters());
}

NullSpaces Study::nullSpaces() {
  control_.say("null spaces: the GC residuals' Jacobian at the truth");
  NullSpaces out;
  const Eigen::MatrixXd J = gcJacobian(truth_, train_, settings_.threads);
  const int p = static_cast<int>(J.cols());
  out.standard = p;
  // Unit-norm columns (a column the GC error does not see at all keeps scale 1).
  Eigen::VectorXd d = J.colwise().norm().transpose();
  for (int k = 0; k < p; ++k)
    if (d[k] == 0.0) d[k] = 1.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J * d.cwiseInverse().asDiagonal(),
                                              Eigen::ComputeThinV);
  const Eigen::VectorXd sigma = svd.singularValues();
  out.gc_singular_values.assign(sigma.data(), sigma.data() + sigma.size());
  int rank = 0;
  for (int k = 0; k < sigma.size(); ++k)
    if (sigma[k] > out.tolerance * sigma[0]) ++rank;
  out.gc_near_null = p - rank;
  const Eigen::MatrixXd gc_null = svd.matrixV().rightCols(p - rank);  // orthonormal, scaled coords
  // The regressor's null space in the same scaled coordinates, orthonormalised.
  const Eigen::MatrixXd regressor_null = d.asDiagonal() * base_.nullSpace();
  out.regressor_null = static_cast<int>(regressor_null.cols());
  if (gc_null.cols() > 0 && regressor_null.cols() > 0) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(regressor_null);
    const Eigen::MatrixXd q =
        qr.householderQ() * Eigen::MatrixXd::Identity(p, regressor_null.cols());
    const Eigen::VectorXd cosines =
        Eigen::JacobiSVD<Eigen::MatrixXd>(q.transpose() * gc_null).singularValues();
    for (int k = 0; k < cosines.size(); ++k)
      out.principal_angles_deg.push_back(std::acos(std::clamp(cosines[k], -1.0, 1.0)) * 180.0 /
                                         M_PI);
  }
  return out;
}

NearTruth Study::nearTruth(int samples, double range, const std::string& estimate,
                           double estimate_gc) {
  control_.say("GC errors of " + std::to_string(samples) + " configurations near the truth");
  NearTruth out;
  out.range = range;
  out.estimate = estimate;
  out.estimate_gc = estimate_gc;
  int below = 0;
  for (int k = 0; k < samples; ++k) {
    // Seeds apart from the initial guess's (settings_.seed).
    const double gc =
        comparison_->testGc(perturbedModel(truth_, range, settings_.seed * 7919 + k + 1));
    out.gc_errors.push_back(gc);
    if (gc <= estimate_gc) ++below;
  }
  out.percentile = samples > 0 ? 100.0 * below / samples : 0.0;
  return out;
}

MethodMetrics Study::run(Method method) {
  const Estimate estimate = runner_->run(method);
  if (method == Method::kOls)
    ols_relative_std_dev_ = estimate.least_squares->estimate.relative_std_dev_percent;
  // A refinement's row starts from the GC error where it started, every other from the guess's.
  return comparison_->measure(methodName(method), estimate.model,
                              isRefined(method) ? estimate.start_gc : initial_gc_,
                              estimate.evaluations, estimate.seconds);
}

}  // namespace dynid
