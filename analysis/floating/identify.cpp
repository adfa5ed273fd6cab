#include "analysis/floating/identify.hpp"

#include <cmath>
#include <limits>

#include "analysis/floating/combined.hpp"
#include "analysis/floating/gc_measure.hpp"
#include "analysis/floating/identifiability.hpp"
#include "core/errors.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"

namespace dynid {

const char* floatingMethodName(FloatingMethod method) {
  switch (method) {
    case FloatingMethod::kOls:
      return "ols";
    case FloatingMethod::kWls:
      return "wls";
    case FloatingMethod::kPc:
      return "pc";
    case FloatingMethod::kCombined:
      return "combined";
  }
  return "?";
}

FloatingMethod parseFloatingMethod(const std::string& text) {
  for (FloatingMethod m :
       {FloatingMethod::kOls, FloatingMethod::kWls, FloatingMethod::kPc, FloatingMethod::kCombined})
    if (text == floatingMethodName(m)) return m;
  throw InputError("`method` is '" + text + "'; a floating base takes ols, wls, pc or combined");
}

void FloatingIdentifyRequest::check() const {
  constexpr const char* kCommand = "identify";
  structural.check();
  checkPriorWeight(prior_weight);
  if (gc) gc->check();
  checkOption(kCommand, "threads", threads, "`threads`");
  if (method != FloatingMethod::kCombined) return;
  if (!gc)
    throw InputError(
        "`method`: combined rolls the data's motion out: it needs `gc` (the segments)");
  checkOption(kCommand, "combined-weight", combined.gc_weight, "`combined_weight`");
  checkOption(kCommand, "combined-seconds", combined.max_seconds, "`combined_seconds`");
  checkOption(kCommand, "combined-iterations", combined.max_iterations, "`combined_iterations`");
}

namespace {
std::string inFile(const FloatingDataset& d) {
  return d.file.empty() ? std::string("the dataset") : "'" + d.file + "'";
}

/// A supported base moves when the RMS of its angular rate reaches this [rad/s] or its linear
/// acceleration's spread about its mean this [m/s^2]: ten times a MEMS IMU's noise over a 100 Hz
/// band (about 0.005 rad/s and 0.02 m/s^2), far below a support that turns or carries the robot (a
/// 0.2 Hz swing of 0.1 rad reaches 0.09 rad/s). The spread, not the RMS: an accelerometer's bias,
/// or gravity leaking through an orientation a degree off (0.17 m/s^2), is constant, and a support
/// cannot accelerate the same way for long.
constexpr double kMovingRate = 0.05, kMovingAcceleration = 0.2;

/// The motion of a robot on a support (a contact on the base body): carried when the base moves
/// in the data, suspended when it is still; a warning says which and why.
FloatingMotion supportedMotion(const FloatingDataset& data, std::vector<std::string>& warnings) {
  const Eigen::Index n = data.twist.cols();
  if (n == 0) return FloatingMotion::kSuspended;
  const double rate = std::sqrt(data.twist.topRows<3>().squaredNorm() / static_cast<double>(n));
  const Eigen::Matrix3Xd linear = data.acceleration.bottomRows<3>();
  const double acceleration = std::sqrt((linear.colwise() - linear.rowwise().mean()).squaredNorm() /
                                        static_cast<double>(n));
  const bool moves = rate >= kMovingRate || acceleration >= kMovingAcceleration;
  warnings.push_back(
      "a contact on the base body: its support " +
      std::string(moves ? "moves the base (carried)" : "holds the base still (suspended)") +
      " by the data, the base's RMS angular rate " + formatNumber(rate, 3) +
      " rad/s and its linear acceleration's spread " + formatNumber(acceleration, 3) +
      " m/s^2 (carried from " + formatNumber(kMovingRate) + " or " +
      formatNumber(kMovingAcceleration) + "); set `motion` to say otherwise");
  return moves ? FloatingMotion::kCarried : FloatingMotion::kSuspended;
}

/// The contacts: the request's, or the dataset's own; each checked against what the dataset
/// measures there.
std::vector<Contact> resolveContacts(const FloatingModel& model,
                                     const FloatingIdentifyRequest& request,
                                     const FloatingDataset& data) {
  std::vector<std::string> specs = request.contacts;
  if (specs.empty()) {
    for (const FloatingDataset::Wrench& w : data.wrenches)
      specs.push_back(w.frame + (w.values.rows() == 6 ? ":frame" : ""));
    for (const FloatingDataset::Flag& f : data.flags)
      if (data.findWrench(f.frame) == nullptr) specs.push_back(f.frame);
  }
  const std::vector<Contact> contacts = contactsOf(model, specs);
  const auto listed = [&](const std::string& frame) {
    for (const Contact& c : contacts)
      if (c.name == frame) return true;
    return false;
  };
  for (const FloatingDataset::Wrench& w : data.wrenches)
    if (!listed(w.frame))
      throw InputError(inFile(data) + " measures a wrench at '" + w.frame +
                       "', which `contacts` lacks: list every contact the robot had");
  for (const FloatingDataset::Flag& f : data.flags)
    if (!listed(f.frame))
      throw InputError(inFile(data) + " flags a contact at '" + f.frame +
                       "', which `contacts` lacks: list every contact the robot had");
  for (const Contact& c : contacts)
    if (const FloatingDataset::Wrench* w = data.findWrench(c.name))
      if (w->values.rows() != c.dimension())
        throw InputError("`contacts`: '" + c.name + "' is a " +
                         (c.kind == Contact::Kind::kFrame
                              ? "frame contact (a wrench), and " + inFile(data) +
                                    " has no moment there (wrench:" + c.name + ":nx, ny, nz)"
                              : "point contact (a force), and " + inFile(data) +
                                    " measures a moment there: declare it " + c.name + ":frame"));
  return contacts;
}

/// Why the dataset cannot feed `set` (empty: it can).
std::string missing(SensorSet set, const FloatingDataset& data,
                    const std::vector<Contact>& contacts) {
  if (set != SensorSet::kWrenches && !data.hasTorques())
    return inFile(data) + " has no joint torques (tau:J columns)";
  if (set == SensorSet::kWrenches && contacts.empty())
    return "no contact carries a wrench (nothing measures the base rows)";
  for (const Contact& c : contacts) {
    if (set == SensorSet::kTorquesAndContactFlags && data.findFlag(c.name) == nullptr)
      return inFile(data) + " has no flag for the contact '" + c.name + "' (contact:" + c.name +
             ")";
    if (set != SensorSet::kTorquesAndContactFlags && data.findWrench(c.name) == nullptr)
      return inFile(data) + " has no wrench at the contact '" + c.name + "' (wrench:" + c.name +
             ":fx, fy, fz)";
  }
  return "";
}

/// Residual percent of `beta` on the set's rows of every sample: ||W beta - y|| / ||y||.
double residualPercent(const FloatingModel& model, const FloatingDataset& dataset,
                       const std::vector<Contact>& contacts, const SensorSetBase& s,
                       const Eigen::VectorXd& beta) {
  FloatingData data(model);
  double residual = 0.0, measured = 0.0;
  for (int k = 0; k < dataset.numSamples(); ++k) {
    const FloatingMeasurement m = floatingMeasurement(model, data, dataset, contacts, s.set, k);
    const Eigen::VectorXd y = sensorMeasurements(s.set, m.tau, m.J, m.forces);
    residual += (s.base.baseRegressor(sensorRows(s.set, m.Y, m.J)) * beta - y).squaredNorm();
    measured += y.squaredNorm();
  }
  return 100.0 * std::sqrt(residual / measured);
}

/// The set's fit: ordinary, or weighted by `shared` variances when another set estimated them,
/// else by its own estimate.
FloatingFit fitSet(const FloatingIdentifyRequest& request, FloatingSetEstimate& out,
                   std::vector<FloatingMeasurement>& samples,
                   const std::optional<ChannelVariances>& shared) {
  const SensorSet set = out.base.set;
  FloatingFitOptions options;
  if (request.method == FloatingMethod::kOls) {
    options.generalized = false;
    return fitFloating(out.base.base, set, samples, options);
  }
  if (!shared) {
    out.variances_from = set;
    return fitFloatingFeasible(out.base.base, set, samples, &out.variances);
  }
  out.variances = *shared;
  out.variances_from = SensorSet::kTorquesAndWrenches;
  for (FloatingMeasurement& m : samples)
    for (Eigen::Index r = 0; r < m.force_variance.size(); ++r)
      m.force_variance[r] =
          m.moment_rows[static_cast<std::size_t>(r)] ? shared->moment : shared->force;
  options.torque_variance = Eigen::VectorXd::Constant(samples.front().tau.size(), shared->torque);
  return fitFloating(out.base.base, set, samples, options);
}

void estimate(const FloatingModel& model, const FloatingIdentifyRequest& request,
              const std::vector<Contact>& contacts, const FloatingDataset& data,
              const FloatingDataset* validation, const std::optional<ChannelVariances>& shared,
              FloatingSetEstimate& out) {
  const SensorSet set = out.base.set;
  FloatingData workspace(model);
  std::vector<FloatingMeasurement> samples;
  for (int k = 0; k < data.numSamples(); ++k)
    samples.push_back(floatingMeasurement(model, workspace, data, contacts, set, k));
  try {
    out.fit = fitSet(request, out, samples, shared);
  } catch (const InputError& e) {
    out.refused = e.what();
    return;
  }
  if (request.method == FloatingMethod::kPc ||
      request.method == FloatingMethod::kCombined) {  // weighted as wls, then held physical
    PhysicalOptions options;
    options.prior_weight = request.prior_weight;
    out.physical = fitFloatingPhysical(model, out.base.base, set, samples, out.variances,
                                       model.standardParameters(), options);
    out.fit.beta = out.physical->beta;
  }
  measureSetEstimate(model, contacts, data, validation, out);
}
}  // namespace

void measureSetEstimate(const FloatingModel& model, const std::vector<Contact>& contacts,
                        const FloatingDataset& data, const FloatingDataset* validation,
                        FloatingSetEstimate& out) {
  out.residual_percent = residualPercent(model, data, contacts, out.base, out.fit.beta);
  out.validation_percent =
      validation != nullptr ? residualPercent(model, *validation, contacts, out.base, out.fit.beta)
                            : std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd error = out.fit.beta - out.model_beta;
  out.model_error_percent = 100.0 * error.norm() / out.model_beta.norm();
  out.model_z_rms =
      std::sqrt(error.cwiseQuotient(out.fit.sd).squaredNorm() / static_cast<double>(error.size()));
}

FloatingMeasurement floatingMeasurement(const FloatingModel& model, FloatingData& data,
                                        const FloatingDataset& dataset,
                                        const std::vector<Contact>& contacts, SensorSet set,
                                        int k) {
  BaseMotion base;
  base.rotation = baseRotation(Eigen::Vector4d(dataset.orientation.col(k)));
  base.twist = dataset.twist.col(k);
  base.acceleration = dataset.acceleration.col(k);
  const Eigen::VectorXd q = dataset.q.col(k), dq = dataset.dq.col(k), ddq = dataset.ddq.col(k);
  FloatingMeasurement m;
  m.Y = floatingRegressor(model, data, base, q, dq, ddq);
  const int n = model.numJoints();
  m.tau = dataset.hasTorques() ? Eigen::VectorXd(dataset.tau.col(k)) : Eigen::VectorXd::Zero(n);
  const bool flags = set == SensorSet::kTorquesAndContactFlags;
  if (const std::string why = missing(set, dataset, contacts); !why.empty())
    throw InputError(std::string(sensorSetName(set)) + ": " + why);
  std::vector<const Contact*> used;
  int rows = 0;
  for (const Contact& c : contacts)
    if (!flags || dataset.findFlag(c.name)->holding[static_cast<std::size_t>(k)]) {
      used.push_back(&c);
      rows += c.dimension();
    }
  m.J.resize(rows, model.numVelocities());
  m.forces = Eigen::VectorXd::Zero(rows);
  m.force_variance = Eigen::VectorXd::Ones(rows);
  m.moment_rows.assign(static_cast<std::size_t>(rows), 0);
  rows = 0;
  for (const Contact* c : used) {
    const int dim = c->dimension();
    m.J.middleRows(rows, dim) = contactJacobian(model, data, *c, q);
    if (c->kind == Contact::Kind::kFrame)
      for (int r = 0; r < 3; ++r) m.moment_rows[static_cast<std::size_t>(rows + r)] = 1;
    if (!flags) {  // the measured wrench, turned from the contact's axes into the base's
      const Eigen::Matrix3d R = contactPose(model, data, *c, q).rotation;
      const Eigen::MatrixXd& w = dataset.findWrench(c->name)->values;
      for (int r = 0; r < dim; r += 3) m.forces.segment<3>(rows + r) = R * w.col(k).segment<3>(r);
    }
    rows += dim;
  }
  return m;
}

FloatingIdentifyOutcome floatingIdentifyRun(const FloatingModel& model,
                                            const FloatingIdentifyRequest& request,
                                            const FloatingDataset& data,
                                            const FloatingDataset* validation) {
  request.check();
  FloatingIdentifyOutcome out;
  out.contacts = resolveContacts(model, request, data);
  if (validation != nullptr) resolveContacts(model, request, *validation);
  out.method = request.method;
  out.samples = data.numSamples();
  out.validation_samples = validation != nullptr ? validation->numSamples() : 0;
  // The structural base's motion class, and the contacts that hold in it (the base's support is
  // the sampler's own when suspended or carried).
  std::vector<Contact> holding;
  bool on_base = false;
  for (const Contact& c : out.contacts) {
    if (c.body < 0)
      on_base = true;
    else
      holding.push_back(c);
  }
  if (request.motion)
    out.motion = *request.motion;
  else
    out.motion = on_base           ? supportedMotion(data, out.warnings)
                 : holding.empty() ? FloatingMotion::kFree
                                   : FloatingMotion::kHolding;
  if (request.method == FloatingMethod::kCombined)  // refused before any fit
    checkCombinedData(data, out.contacts, out.motion);
  const bool supported =
      out.motion == FloatingMotion::kSuspended || out.motion == FloatingMotion::kCarried;
  std::vector<SensorSet> sets = request.sensors;
  for (SensorSet set : sets)
    if (const std::string why = missing(set, data, out.contacts); !why.empty())
      throw InputError("`sensors`: " + std::string(sensorSetName(set)) + ": " + why);
  if (sets.empty())
    for (SensorSet set : kSensorSets)
      if (missing(set, data, out.contacts).empty()) sets.push_back(set);
  if (sets.empty())
    throw InputError(inFile(data) + " feeds no sensor set: " +
                     missing(SensorSet::kTorquesAndWrenches, data, out.contacts));
  const FloatingStructuralOptions options{request.structural, supported ? holding : out.contacts,
                                          out.motion};
  const Eigen::VectorXd theta = model.standardParameters();
  for (SensorSetBase& base : floatingStructuralBase(model, sets, options)) {
    out.sets.emplace_back();
    out.sets.back().model_beta = base.base.project(theta);
    out.sets.back().base = std::move(base);
  }
  // The same sensors feed every set: torques_wrenches, which reads them all, estimates their
  // noise first (weighted fits), and the other sets are weighted by it.
  std::optional<ChannelVariances> shared;
  for (FloatingSetEstimate& s : out.sets)
    if (s.base.set == SensorSet::kTorquesAndWrenches) {
      estimate(model, request, out.contacts, data, validation, std::nullopt, s);
      if (s.refused.empty() && request.method != FloatingMethod::kOls) shared = s.variances;
    }
  for (FloatingSetEstimate& s : out.sets)
    if (s.base.set != SensorSet::kTorquesAndWrenches)
      estimate(model, request, out.contacts, data, validation, shared, s);
  if (request.method == FloatingMethod::kCombined)
    combineFloatingSets(model, request, data, validation, out);
  measureFloatingGc(model, request, data, validation, out);
  return out;
}

FloatingIdentifyRequest pairedRequest(const FloatingIdentifyRequest& request,
                                      const FloatingIdentifyOutcome& loaded) {
  FloatingIdentifyRequest out = request;
  out.motion = loaded.motion;
  if (out.method != FloatingMethod::kCombined) out.gc.reset();  // combined's rollouts need it
  return out;
}

}  // namespace dynid
