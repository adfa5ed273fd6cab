#include "analysis/payload/payload.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "analysis/payload/attach.hpp"
#include "analysis/payload/body.hpp"
#include "analysis/payload/quantities.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/prepare_record.hpp"
#include "core/checks.hpp"
#include "core/drive_terms.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/parameters.hpp"
#include "core/regressor.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "data/urdf_writeback.hpp"

namespace dynid {

namespace {

/// The share of a drive gain its 95 % half-width may reach for it to count as determined: 0.5 %
/// (so that a scale reported determined is within 1 % at four standard deviations).
constexpr double kGainShare = 0.005;

/// Median sample step [s].
double medianStep(const Eigen::VectorXd& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> steps(static_cast<std::size_t>(t.size() - 1));
  for (Eigen::Index k = 0; k + 1 < t.size(); ++k) steps[k] = t[k + 1] - t[k];
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

/// Mean squared position difference of loaded sample k against unloaded sample k + s over the
/// overlap, every `stride`-th sample.
double mismatch(const Eigen::MatrixXd& ql, const Eigen::MatrixXd& qu, long s, long stride) {
  const long nl = ql.cols(), nu = qu.cols();
  const long first = std::max(0L, -s), last = std::min(nl, nu - s);
  double sum = 0.0;
  long count = 0;
  for (long k = first; k < last; k += stride, ++count)
    sum += (ql.col(k) - qu.col(k + s)).squaredNorm();
  return count > 0 ? sum / count : std::numeric_limits<double>::infinity();
}

struct Alignment {
  long shift = 0;  // unloaded sample = loaded sample + shift
  Eigen::VectorXd rms;
};

/// The integer sample shift that best overlays the unloaded run's positions on the loaded run's
/// (overlap at least half the shorter run): a coarse search on every D-th shift and sample, then
/// every shift around the best.
Alignment alignRuns(const Trajectory& loaded, const Trajectory& unloaded) {
  const long nl = loaded.numSamples(), nu = unloaded.numSamples();
  const long overlap = std::min(nl, nu) / 2;
  const long stride = std::max(1L, std::min(nl, nu) / 1000);
  long best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (long s = -(nl - overlap); s <= nu - overlap; s += stride) {
    const double c = mismatch(loaded.q, unloaded.q, s, stride);
    if (c < best_cost) best_cost = c, best = s;
  }
  const long centre = best;
  best_cost = std::numeric_limits<double>::infinity();
  for (long s = std::max(centre - stride, -(nl - overlap));
       s <= std::min(centre + stride, nu - overlap); ++s) {
    const double c = mismatch(loaded.q, unloaded.q, s, 1);
    if (c < best_cost) best_cost = c, best = s;
  }
  Alignment out;
  out.shift = best;
  const long first = std::max(0L, -best), last = std::min(nl, nu - best);
  out.rms = ((loaded.q.middleCols(first, last - first) -
              unloaded.q.middleCols(first + best, last - first))
                 .rowwise()
                 .squaredNorm() /
             static_cast<double>(std::max(1L, last - first)))
                .cwiseSqrt();
  return out;
}

/// The gradient of f at `at` by central differences (steps of 1e-6 of each parameter's size).

}  // namespace

void PayloadRequest::check() const {
  checkOption("payload", "prior-weight", prior_weight, "`prior_weight`");
  if (known_mass) checkOption("payload", "payload-mass", *known_mass, "`known_mass`");
  checkOption("payload", "max-motion-difference", max_motion_difference, "`max_motion_difference`");
  if (known_com && !known_mass)
    throw InputError("known_com: a known centre of mass needs the known mass");
  if (known_com && !known_com->allFinite())
    throw InputError("known_com: the centre of mass must be finite");
  if (known_mass && unloaded_file.empty() && unloaded == nullptr)
    throw InputError("known_mass: drive gains need the unloaded run of the same motion");
  if (!tool.translation.allFinite() || !tool.rotation.allFinite() ||
      tool.translation.norm() > kMaxModelLength ||
      !(tool.rotation.transpose() * tool.rotation).isApprox(Eigen::Matrix3d::Identity(), 1e-9) ||
      tool.rotation.determinant() < 0.0)
    throw InputError("tool: the attachment frame must be a finite rigid transform");
  if (prior) {
    if (!prior->allFinite() || !((*prior)[0] > 0.0))
      throw InputError("prior: the prior payload must have a finite, positive mass");
    const auto violations = checkPhysicalConsistency(fromStandardVector(*prior), 0, "prior");
    if (!violations.empty())
      throw InputError("prior: the prior payload is not physically consistent (" +
                       violations[0].condition + ": " + violations[0].detail + ")");
  }
  if (data_file.empty() && data == nullptr)
    throw InputError("data_file: a log with the payload attached is needed");
}

namespace {

/// Advice when the mass, centre of mass or inertia is not determined.
void adviseOnMotion(PayloadOutcome& out, const Trajectory& loaded) {
  const int n = loaded.numJoints();
  // Advice: the wrist joint that moved least.
  bool inertia_undetermined = false, com_undetermined = false;
  for (const PayloadQuantity& q : out.quantities) {
    if (q.group == "principal moments" && !q.determined) inertia_undetermined = true;
    if (q.group == "centre of mass" && !q.determined) com_undetermined = true;
  }
  if (!out.quantities[0].determined)
    out.advice.push_back("the mass is not determined: the payload (" + formatNumber(out.mass, 3) +
                         " kg) is below what this log resolves (" +
                         formatNumber(out.smallest_mass, 3) +
                         " kg to +-20 %): record a longer or faster motion, or use a less noisy "
                         "torque signal");
  if (com_undetermined || inertia_undetermined || !out.unseen.empty()) {
    int least = std::max(0, n - 3);
    double least_rms = std::numeric_limits<double>::infinity();
    for (int j = std::max(0, n - 3); j < n; ++j) {
      const double rms = std::sqrt(loaded.dq.row(j).squaredNorm() / loaded.numSamples());
      if (rms < least_rms) least_rms = rms, least = j;
    }
    out.advice.push_back(
        std::string(inertia_undetermined ? "the inertia" : "the centre of mass") +
        " is not determined by this motion: rotate the wrist more, joint " +
        std::to_string(least + 1) + " above all (RMS speed " + formatNumber(least_rms, 3) +
        " rad/s in this log), and in several orientations; dynid excite `payload` designs such a "
        "motion");
  }
}

/// The arm's friction terms re-estimated with the payload: each extra column's arm value, value
/// with the payload and standard deviation.
std::vector<FrictionChange> frictionChanges(const ParameterLayout& layout,
                                            const std::vector<int>& extra_columns,
                                            const Eigen::VectorXd& theta_arm,
                                            const PayloadFit& fit) {
  std::vector<FrictionChange> out;
  const std::vector<std::string> names = standardParameterNames(layout);
  for (std::size_t i = 0; i < extra_columns.size(); ++i) {
    FrictionChange c;
    c.name = names[static_cast<std::size_t>(extra_columns[i])];
    c.arm = theta_arm[extra_columns[i]];
    c.with_payload = c.arm + fit.extra[static_cast<Eigen::Index>(i)];
    c.std_dev =
        std::sqrt(fit.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)));
    out.push_back(c);
  }
  return out;
}

/// The arm's URDF (carrying the arm's parameters when it was given as a model) with the payload
/// as a fixed link on its attachment link.
std::string urdfWithPayload(const PayloadRequest& request, const Model& arm,
                            const PayloadOutcome& out) {
  std::string text = readFile(request.urdf_file);
  if (request.urdf_carries_arm) text = urdfWithParameters(text, request.urdf_file, arm);
  return urdfWithFixedBody(text, request.urdf_file, out.link_name, "payload", request.tool,
                           fromStandardVector(out.standard));
}

/// Drive gains from the known mass: the body rows (the extra columns dropped) fitted with it.
DriveGains driveGains(const PayloadRequest& request, const PayloadRows& rows, int f,
                      const Eigen::VectorXd& arm_difference) {
  const int n = rows.numJoints();
  DriveGains gains;
  {
    PayloadRows body_rows(n, 0);
    body_rows.reserve(rows.numSamples());
    const Eigen::MatrixXd design = rows.design();
    const Eigen::VectorXd target = rows.target();
    const Eigen::MatrixXd none(n, 0);
    for (int k = 0; k < rows.numSamples(); ++k)
      body_rows.add(design.block(static_cast<Eigen::Index>(k) * n, f, n, 10), none,
                    target.segment(static_cast<Eigen::Index>(k) * n, n));
    const GainFit g =
        fitDriveGains(body_rows, *request.known_mass, request.known_com, 0, arm_difference);
    gains.scale = g.scale;
    gains.scale_std = g.scale_std;
    gains.iterations = g.iterations;
    for (int j = 0; j < n; ++j)
      gains.determined.push_back(kZ95 * g.scale_std[j] <= kGainShare * std::abs(g.scale[j]) ? 1
                                                                                            : 0);
    const PreparationFound found = findPreparation(request.data_file);
    if (found.record && static_cast<int>(found.record->torque_constants.size()) == n)
      for (int j = 0; j < n; ++j)
        gains.torque_constants.push_back(found.record->torque_constants[j] * g.scale[j]);
  }

  return gains;
}

/// The unloaded run of a pair, aligned on the loaded run by position (refused when the motions
/// differ), and its residual against the arm model; `pair` false without one.
struct UnloadedRun {
  bool pair = false;
  Trajectory trajectory;
  Eigen::MatrixXd residual;  // n x its samples
  long shift = 0;            // loaded sample k pairs with unloaded sample k + shift
};
UnloadedRun unloadedRun(const PayloadRequest& request, const Trajectory& loaded, Data& data,
                        PayloadOutcome& out) {
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const Eigen::VectorXd theta_arm = arm.standardParameters();
  UnloadedRun run;
  run.pair = !request.unloaded_file.empty() || request.unloaded != nullptr;
  if (!run.pair) return run;
  Trajectory& unloaded = run.trajectory;
  {
    unloaded = request.unloaded ? *request.unloaded : readDatasetCsv(request.unloaded_file, n);
    if (unloaded.numJoints() != n)
      throw InputError(request.unloaded_file + ": " + std::to_string(unloaded.numJoints()) +
                       " joints, the arm has " + std::to_string(n));
    const double dl = medianStep(loaded.time), du = medianStep(unloaded.time);
    if (unloaded.numSamples() < 2 || !(std::abs(dl - du) <= 1e-6 * dl))
      throw InputError(request.unloaded_file + ": sampled every " + formatNumber(du) +
                       " s, the loaded run every " + formatNumber(dl) +
                       " s: prepare both at one rate (dynid prepare `rate`)");
    const Alignment a = alignRuns(loaded, unloaded);
    run.shift = a.shift;
    out.shift = static_cast<double>(a.shift) * dl;
    out.motion_difference = a.rms;
    for (int j = 0; j < n; ++j)
      if (!(a.rms[j] <= request.max_motion_difference))
        throw InputError(request.unloaded_file + ": its motion differs from " + request.data_file +
                         "'s: joint " + std::to_string(j + 1) + " is " + formatNumber(a.rms[j], 3) +
                         " rad RMS apart after the best time shift (" + formatNumber(out.shift, 4) +
                         " s; at most " + formatNumber(request.max_motion_difference) +
                         " rad): record the same commanded motion with and without the payload, "
                         "or, when the payload's weight alone pulls the arm off its path, allow "
                         "more with `max_motion_difference` (each run's own motion is used, so "
                         "the arm model's errors then cancel less)");
    run.residual.resize(n, unloaded.numSamples());
    for (int k = 0; k < unloaded.numSamples(); ++k)
      run.residual.col(k) =
          unloaded.tau.col(k) - jointTorqueRegressor(arm, data, unloaded.q.col(k),
                                                     unloaded.dq.col(k), unloaded.ddq.col(k)) *
                                    theta_arm;
  }
  return run;
}

/// With refit_friction: the arm's non-inertial drive-term columns of the joints that move.
std::vector<int> frictionColumns(const PayloadRequest& request, const Trajectory& loaded) {
  const ParameterLayout layout = request.arm.parameterLayout();
  const int n = request.arm.numJoints();
  std::vector<int> extra_columns;
  if (request.refit_friction) {
    for (int j = 0; j < n; ++j) {
      const double rms = std::sqrt(loaded.dq.row(j).squaredNorm() / loaded.numSamples());
      if (!(rms > 1e-3)) continue;
      for (int t = 0; t < kDriveTermCount; ++t)
        if (layout.drives.has(static_cast<DriveTerm>(t)) && !kDriveTermTable[t].inertial)
          extra_columns.push_back(layout.driveIndex(j, t));
    }
    if (extra_columns.empty())
      throw InputError(
          "refit_friction: the arm model has no friction terms (give its drive "
          "terms, e.g. `drive_terms` fv,fc) or no joint moves");
  }
  return extra_columns;
}

/// A log of another robot (or in other units): a payload heavier than the arm, a residual that
/// follows the arm's own torque (refused); a heavy payload, residuals far above prepare's noise
/// (warned).
void checkPlausible(const PayloadRequest& request, const PayloadRows& rows, const PayloadFit& fit,
                    const Eigen::MatrixXd& arm_torque, PayloadOutcome& out) {
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const int f = static_cast<int>(fit.extra.size());
  // A log of another robot: a payload heavier than the whole arm.
  const double arm_mass = totalMass(arm);
  if (std::abs(out.least_squares[0]) > arm_mass)
    throw InputError(
        request.data_file + ": explaining it takes a payload of " +
        formatNumber(out.least_squares[0], 3) + " kg, more than the whole arm (" +
        formatNumber(arm_mass, 3) + " kg): is it a log of this robot (" + arm.name +
        "), with the torques in N m" +
        (out.mode == "difference" ? ", and the unloaded run of the same robot?" : "?"));
  if (std::abs(out.least_squares[0]) > 0.5 * arm_mass)
    out.warnings.push_back("the payload (" + formatNumber(out.least_squares[0], 3) +
                           " kg) weighs more than half the arm (" + formatNumber(arm_mass, 3) +
                           " kg): check that the log is of this robot and in N m");
  if (out.mode == "single") {
    // The residual against the arm model's own torque, over all joints: a log of another robot
    // (or in other units) leaves a residual that is the arm's torque scaled; noise and a fair
    // model's errors do not.
    const Eigen::MatrixXd design = rows.design();
    const Eigen::VectorXd target = rows.target();
    Eigen::VectorXd at(f + 10);
    at << fit.extra, fit.theta;
    const Eigen::VectorXd residual = target - design * at;
    const Eigen::Map<const Eigen::VectorXd> model(arm_torque.data(), residual.size());
    const double ra = residual.dot(model), aa = model.squaredNorm(), rr = residual.squaredNorm();
    if (aa > 0.0 && rr > 0.0) {
      const double slope = ra / aa, r2 = ra * ra / (aa * rr);
      if (std::abs(slope) > 0.25 && r2 > 0.5)
        throw InputError(request.data_file + ": its torques are the arm model's times " +
                         formatNumber(1.0 + slope, 3) +
                         " (what the model and a payload leave unexplained follows the arm's own "
                         "torque, R^2 " +
                         formatNumber(r2, 2) + "): is it a log of this robot (" + arm.name +
                         "), in N m, with the right torque constants?");
    }
  }

  // Residuals far above the noise prepare measured: the estimate carries the arm model's errors.
  if (const PreparationFound found = findPreparation(request.data_file);
      out.mode == "single" && found.record &&
      static_cast<int>(found.record->tau_noise_rms.size()) == n) {
    std::string joints;
    for (int j = 0; j < n; ++j) {
      const double noise = found.record->tau_noise_rms[j];
      if (std::isfinite(noise) && noise > 0.0 && out.residual_rms[j] > 5.0 * noise)
        joints += (joints.empty() ? "" : ", ") + std::to_string(j + 1) + " (" +
                  formatNumber(out.residual_rms[j] / noise, 3) + "x)";
    }
    if (!joints.empty())
      out.warnings.push_back(
          "the arm model and the payload leave more than 5 times the noise prepare measured "
          "unexplained on joint " +
          joints +
          ": the payload carries the arm model's errors; an unloaded run of the same motion "
          "(`unloaded`) cancels them");
  }
}

/// The figure's samples: the payload's torque, measured and estimated, at most 2000.
void plotSamples(const PayloadRows& rows, const PayloadFit& fit, const Trajectory& loaded,
                 const std::vector<int>& used, PayloadOutcome& out) {
  const int n = loaded.numJoints();
  const int f = static_cast<int>(fit.extra.size());
  const int keep = std::min(out.samples, 2000);
  out.plot_time.resize(keep);
  out.plot_measured.resize(n, keep);
  out.plot_predicted.resize(n, keep);
  const Eigen::MatrixXd design = rows.design();
  const Eigen::VectorXd target = rows.target();
  Eigen::VectorXd at(f + 10);
  at << fit.extra, fit.theta;
  for (int i = 0; i < keep; ++i) {
    const long k = static_cast<long>(static_cast<double>(i) * out.samples / keep);
    out.plot_time[i] = loaded.time[used[k]];
    out.plot_measured.col(i) = target.segment(k * n, n);
    out.plot_predicted.col(i) = design.middleRows(k * n, n) * at;
  }
}

}  // namespace

namespace {

/// The outcome's echo of the request: the attachment link, the runs and the prior.
PayloadOutcome outcomeOf(const PayloadRequest& request) {
  const Model& arm = request.arm;
  PayloadOutcome out;
  out.link = linkIndex(arm, request.link);
  out.link_name = arm.link_names[out.link];
  out.robot = arm.name;
  out.arm_source = request.arm_source;
  out.arm = request.arm;
  out.arm_model = request.arm_model;
  out.data_file = request.data_file;
  out.unloaded_file = request.unloaded_file;
  out.tool = request.tool;
  out.mode = request.unloaded_file.empty() && request.unloaded == nullptr ? "single" : "difference";
  out.prior_weight = request.prior_weight;
  out.prior_given = request.prior.has_value();
  return out;
}

/// The fit's estimate, covariance (the payload's 10 parameters), residuals and solver outcome.
void takeFit(const PayloadFit& fit, PayloadOutcome& out) {
  out.least_squares = fit.least_squares;
  out.standard = fit.theta;
  out.prior = fit.prior;
  out.covariance = fit.covariance.bottomRightCorner(10, 10);
  out.noise = fit.noise;
  out.residual_rms = fit.residual_rms;
  out.target_rms = fit.target_rms;
  out.batch = fit.batch;
  out.least_squares_consistent = fit.least_squares_consistent;
  out.converged = fit.converged;
  out.termination = fit.termination;
}

}  // namespace

PayloadOutcome payloadRun(const PayloadRequest& request) {
  request.check();
  const Model& arm = request.arm;
  const int n = arm.numJoints();
  const ParameterLayout layout = arm.parameterLayout();
  PayloadOutcome out = outcomeOf(request);

  const Trajectory loaded = request.data ? *request.data : readDatasetCsv(request.data_file, n);
  if (loaded.numJoints() != n)
    throw InputError(request.data_file + ": " + std::to_string(loaded.numJoints()) +
                     " joints, the arm has " + std::to_string(n));
  if (loaded.numSamples() < 2) throw InputError(request.data_file + ": fewer than 2 samples");
  const Eigen::VectorXd theta_arm = arm.standardParameters();
  Data data(arm);
  const Matrix10d to_link = standardTransform(request.tool);

  // The unloaded run: aligned on the loaded run's samples, its residual against the arm model.
  const UnloadedRun unloaded_run = unloadedRun(request, loaded, data, out);
  const bool pair = unloaded_run.pair;
  const Trajectory& unloaded = unloaded_run.trajectory;
  const Eigen::MatrixXd& unloaded_residual = unloaded_run.residual;
  const long shift = unloaded_run.shift;

  // The extra columns: the arm's non-inertial drive terms of the joints that move.
  const std::vector<int> extra_columns = frictionColumns(request, loaded);
  const int f = static_cast<int>(extra_columns.size());
  PayloadRows rows(n, f);
  rows.reserve(loaded.numSamples());
  Eigen::MatrixXd extra(n, f);
  std::vector<int> used;                               // loaded samples in the problem
  Eigen::MatrixXd arm_torque(n, loaded.numSamples());  // of the samples used, in order
  // With a pair: the arm model's torque at the loaded sample minus at the unloaded one, for the
  // drive gains (the targets have it subtracted; measured currents scale it too).
  Eigen::VectorXd arm_difference(pair ? static_cast<Eigen::Index>(n) * loaded.numSamples() : 0);
  for (int k = 0; k < loaded.numSamples(); ++k) {
    const long u = k + shift;
    if (pair && (u < 0 || u >= unloaded.numSamples())) continue;
    const Eigen::MatrixXd& Y =
        jointTorqueRegressor(arm, data, loaded.q.col(k), loaded.dq.col(k), loaded.ddq.col(k));
    const Eigen::VectorXd model_torque = Y * theta_arm;
    Eigen::VectorXd target = loaded.tau.col(k) - model_torque;
    if (pair) {
      target -= unloaded_residual.col(u);
      arm_difference.segment(static_cast<Eigen::Index>(used.size()) * n, n) =
          model_torque - (unloaded.tau.col(u) - unloaded_residual.col(u));
    }
    for (int i = 0; i < f; ++i) extra.col(i) = Y.col(extra_columns[i]);
    rows.add(Y.middleCols(layout.linkIndex(out.link, 0), 10) * to_link, extra, target);
    arm_torque.col(static_cast<Eigen::Index>(used.size())) = model_torque;
    used.push_back(k);
  }
  out.samples = rows.numSamples();

  PayloadFitOptions options;
  options.prior = request.prior;
  options.prior_weight = request.prior_weight;
  const PayloadFit fit = fitPayload(rows, options);
  takeFit(fit, out);

  checkPlausible(request, rows, fit, arm_torque, out);
  describeBody(out, fit);
  adviseOnMotion(out, loaded);
  if (!out.least_squares_consistent)
    out.warnings.push_back(
        "the least-squares payload is not physically consistent: the consistent estimate is held "
        "inside the physical set by the prior, and its intervals are those of least squares");

  out.friction = frictionChanges(layout, extra_columns, theta_arm, fit);

  if (request.known_mass)
    out.gains = driveGains(request, rows, f,
                           arm_difference.head(static_cast<Eigen::Index>(used.size()) * n));

  plotSamples(rows, fit, loaded, used, out);
  if (!request.urdf_file.empty()) out.urdf = urdfWithPayload(request, arm, out);
  return out;
}

void PayloadOutcome::setBody(const Vector10d& body) {
  const PrincipalBody principal = principalBody(body);
  standard = body;
  mass = principal.mass;
  com = principal.com;
  principal_moments = principal.moments;
  principal_axes = principal.axes;
  inertia_com = inertiaAboutCom(fromStandardVector(body));
}

}  // namespace dynid
