#include "identifiability/floating/sensor_sets.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/LU>
#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea.hpp"
#include "identifiability/observation.hpp"

namespace dynid {

const char* sensorSetName(SensorSet set) {
  switch (set) {
    case SensorSet::kWrenches:
      return "wrenches";
    case SensorSet::kTorquesAndWrenches:
      return "torques_wrenches";
    case SensorSet::kTorquesAndContactFlags:
      return "torques_contacts";
  }
  return "unknown";
}

const char* sensorSetDescription(SensorSet set) {
  switch (set) {
    case SensorSet::kWrenches:
      return "contact wrenches only (force plates or foot force-torque sensors): the six base rows";
    case SensorSet::kTorquesAndWrenches:
      return "joint torques and contact wrenches: every row";
    case SensorSet::kTorquesAndContactFlags:
      return "joint torques and which contacts hold, not their forces: the rows orthogonal to the "
             "contact forces";
  }
  return "";
}

SensorSet parseSensorSet(std::string_view text) {
  for (SensorSet set : kSensorSets)
    if (text == sensorSetName(set)) return set;
  throw InputError("`sensors` is '" + std::string(text) +
                   "'; expected wrenches, torques_wrenches or torques_contacts");
}

const char* floatingMotionName(FloatingMotion motion) {
  switch (motion) {
    case FloatingMotion::kHolding:
      return "holding";
    case FloatingMotion::kFree:
      return "free";
    case FloatingMotion::kSuspended:
      return "suspended";
    case FloatingMotion::kCarried:
      return "carried";
  }
  return "unknown";
}

FloatingMotion parseFloatingMotion(std::string_view text) {
  for (FloatingMotion m : {FloatingMotion::kHolding, FloatingMotion::kFree,
                           FloatingMotion::kSuspended, FloatingMotion::kCarried})
    if (text == floatingMotionName(m)) return m;
  throw InputError("`motion` is '" + std::string(text) +
                   "'; expected holding, free, suspended or carried");
}

namespace {
/// An orthonormal basis of J's null space ((6 + n) x (6 + n - rank J)); the identity for no rows.
Eigen::MatrixXd nullSpaceBasis(const Eigen::MatrixXd& J, int nv) {
  if (J.rows() == 0) return Eigen::MatrixXd::Identity(nv, nv);
  // Q of J^T's column-pivoted QR: its first rank columns span J's row space, the rest its
  // complement, the null space of J.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J.transpose());
  const Eigen::MatrixXd Q = qr.householderQ();
  return Q.rightCols(nv - qr.rank());
}

void checkRows(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& contact_jacobian) {
  if (Y.rows() < 6 || (contact_jacobian.rows() > 0 && contact_jacobian.cols() != Y.rows()))
    throw InputError("a floating regressor has " + std::to_string(Y.rows()) +
                     " rows and the contacts' Jacobian " + std::to_string(contact_jacobian.cols()) +
                     " columns: they must be the same (6 + joints)");
}
}  // namespace

Eigen::MatrixXd sensorRows(SensorSet set, const Eigen::MatrixXd& Y,
                           const Eigen::MatrixXd& contact_jacobian) {
  checkRows(Y, contact_jacobian);
  switch (set) {
    case SensorSet::kWrenches:
      return Y.topRows<6>();
    case SensorSet::kTorquesAndWrenches:
      return Y;
    case SensorSet::kTorquesAndContactFlags:
      return nullSpaceBasis(contact_jacobian, static_cast<int>(Y.rows())).transpose() * Y;
  }
  return Y;
}

Eigen::VectorXd sensorMeasurements(SensorSet set, const Eigen::VectorXd& tau,
                                   const Eigen::MatrixXd& contact_jacobian,
                                   const Eigen::VectorXd& contact_forces) {
  const int nv = 6 + static_cast<int>(tau.size());
  if (contact_jacobian.rows() > 0 && contact_jacobian.cols() != nv)
    throw InputError("the contacts' Jacobian has " + std::to_string(contact_jacobian.cols()) +
                     " columns, not 6 + joints = " + std::to_string(nv));
  if (set != SensorSet::kTorquesAndContactFlags && contact_forces.size() != contact_jacobian.rows())
    throw InputError("the contacts' forces have " + std::to_string(contact_forces.size()) +
                     " entries and their Jacobian " + std::to_string(contact_jacobian.rows()) +
                     " rows: one per force component of each active contact");
  Eigen::VectorXd full = Eigen::VectorXd::Zero(nv);
  full.tail(nv - 6) = tau;
  switch (set) {
    case SensorSet::kWrenches:
      if (contact_jacobian.rows() == 0) return Eigen::VectorXd::Zero(6);
      return contact_jacobian.leftCols<6>().transpose() * contact_forces;
    case SensorSet::kTorquesAndWrenches:
      if (contact_jacobian.rows() > 0) full += contact_jacobian.transpose() * contact_forces;
      return full;
    case SensorSet::kTorquesAndContactFlags:
      return nullSpaceBasis(contact_jacobian, nv).transpose() * full;
  }
  return full;
}

std::vector<int> floatingPreference(const FloatingModel& model) {
  const ParameterLayout layout = model.limbs().parameterLayout();
  const std::vector<int> base = defaultPreference(1, kLinkParameterCount);
  std::vector<int> out = base;
  for (int k : defaultPreference(layout.num_links, layout.perLink()))
    out.push_back(FloatingModel::limbColumn(k));
  return out;
}

namespace {
/// One random state's regressor and its active contacts' Jacobian.
struct RandomState {
  Eigen::MatrixXd Y, J;
};

}  // namespace

FloatingStateSampler::FloatingStateSampler(const FloatingModel& model,
                                           const FloatingStructuralOptions& options)
    : model_(model), options_(options), rng_(options.structural.seed), data_(model) {}

FloatingState FloatingStateSampler::generic() {
  const int n = model_.numJoints();
  FloatingState out = configuration();
  Eigen::VectorXd v(6 + n), a(6 + n);
  for (int k = 0; k < 6 + n; ++k)
    v[k] = k < 6 ? uniform(1.0) : uniform(2.0), a[k] = k < 6 ? uniform(3.0) : uniform(5.0);
  setMotion(out, v, a);
  return out;
}

FloatingState FloatingStateSampler::holding() {
  const int n = model_.numJoints();
  for (int attempt = 0; attempt < 200; ++attempt) {
    FloatingState out = configuration();
    for (int c = 0; c < static_cast<int>(options_.contacts.size()); ++c)
      if (unit_(rng_) < 0.5) out.active.push_back(c);
    const Eigen::MatrixXd J = contactRows(out.active, out.q);
    if (J.rows() == 0 || Eigen::FullPivLU<Eigen::MatrixXd>(J.leftCols<6>()).rank() < 6) continue;
    const Eigen::MatrixXd N = Eigen::FullPivLU<Eigen::MatrixXd>(J).kernel();
    const Eigen::VectorXd v = N * randomVector(static_cast<int>(N.cols()), 1.0);
    const double h = 1e-6;
    const Eigen::VectorXd bias = (contactRows(out.active, out.q + h * v.tail(n)) -
                                  contactRows(out.active, out.q - h * v.tail(n))) *
                                 v / (2 * h);
    const Eigen::VectorXd a = N * randomVector(static_cast<int>(N.cols()), 3.0) -
                              J.completeOrthogonalDecomposition().solve(bias);
    setMotion(out, v, a);
    return out;
  }
  throw InputError(
      "no subset of the `contacts` can carry every base wrench (their Jacobians' "
      "base columns never reach rank 6 in 200 random states): give frame contacts "
      "(flat feet) or three or more points not on one line");
}

FloatingState FloatingStateSampler::suspended() {
  const int n = model_.numJoints();
  FloatingState out = configuration();
  out.base_held = true;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(6 + n), a = Eigen::VectorXd::Zero(6 + n);
  v.tail(n) = randomVector(n, 2.0);
  a.tail(n) = randomVector(n, 5.0);
  setMotion(out, v, a);
  return out;
}

FloatingState FloatingStateSampler::carried() {
  FloatingState out = generic();
  out.base_held = true;
  return out;
}

FloatingState FloatingStateSampler::flight() {
  const int n = model_.numJoints();
  FloatingState out = generic();
  const Eigen::VectorXd torque = randomVector(n, 10.0);
  const Eigen::VectorXd acc = floatingForwardDynamics(model_, data_, out.base, out.q, out.dq,
                                                      torque, Vector6<double>::Zero());
  out.base.acceleration = acc.head<6>();
  out.ddq = acc.tail(n);
  return out;
}

FloatingState FloatingStateSampler::next() {
  switch (options_.motion) {
    case FloatingMotion::kHolding:
      return holding();
    case FloatingMotion::kFree:
      return flight();
    case FloatingMotion::kSuspended:
      return suspended();
    case FloatingMotion::kCarried:
      return carried();
  }
  return generic();
}

Eigen::MatrixXd FloatingStateSampler::jacobian(const FloatingState& state) {
  const Eigen::MatrixXd contacts = contactRows(state.active, state.q);
  if (!state.base_held) return contacts;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(contacts.rows() + 6, model_.numVelocities());
  out.topLeftCorner<6, 6>().setIdentity();
  out.bottomRows(contacts.rows()) = contacts;
  return out;
}

Eigen::MatrixXd FloatingStateSampler::contactRows(const std::vector<int>& active,
                                                  const Eigen::VectorXd& q) {
  int rows = 0;
  for (int c : active) rows += options_.contacts[static_cast<std::size_t>(c)].dimension();
  Eigen::MatrixXd J(rows, model_.numVelocities());
  rows = 0;
  for (int c : active) {
    const Contact& contact = options_.contacts[static_cast<std::size_t>(c)];
    J.middleRows(rows, contact.dimension()) = contactJacobian(model_, data_, contact, q);
    rows += contact.dimension();
  }
  return J;
}

Eigen::MatrixXd FloatingStateSampler::regressor(const FloatingState& state) {
  return floatingRegressor(model_, data_, state.base, state.q, state.dq, state.ddq);
}

double FloatingStateSampler::uniform(double half) { return half * (2.0 * unit_(rng_) - 1.0); }

Eigen::VectorXd FloatingStateSampler::randomVector(int size, double half) {
  Eigen::VectorXd out(size);
  for (int k = 0; k < size; ++k) out[k] = uniform(half);
  return out;
}

FloatingState FloatingStateSampler::configuration() {
  const Model& limbs = model_.limbs();
  FloatingState out;
  Eigen::Vector4d quaternion;
  for (int k = 0; k < 4; ++k) quaternion[k] = normal_(rng_);  // uniform on the sphere
  out.base.rotation = baseRotation(Eigen::Vector4d(quaternion.normalized()));
  out.q.resize(limbs.numJoints());
  for (int i = 0; i < limbs.numJoints(); ++i) {
    const auto [lower, upper] = randomStateRange(limbs, i);
    out.q[i] = lower + (upper - lower) * unit_(rng_);
  }
  return out;
}

void FloatingStateSampler::setMotion(FloatingState& state, const Eigen::VectorXd& v,
                                     const Eigen::VectorXd& a) {
  const int n = model_.numJoints();
  state.base.twist = v.head<6>();
  state.base.acceleration = a.head<6>();
  state.dq = v.tail(n);
  state.ddq = a.tail(n);
}

namespace {
/// The standard parameters whose unit vectors lie in W's row space: no null-space component.
std::vector<int> determinedAlone(const BaseParameters& base) {
  const Eigen::MatrixXd N = base.nullSpace();
  std::vector<int> out;
  for (int j = 0; j < base.numStandard(); ++j) {
    if (std::find(base.zero_columns.begin(), base.zero_columns.end(), j) != base.zero_columns.end())
      continue;
    // N's columns are in physical units; normalised, a row of N with no weight means e_j is
    // orthogonal to the null space.
    double largest = 0.0;
    for (int c = 0; c < N.cols(); ++c)
      largest = std::max(largest, std::abs(N(j, c)) / N.col(c).norm());
    if (largest <= 1e-9) out.push_back(j);
  }
  return out;
}
}  // namespace

std::vector<SensorSetBase> floatingStructuralBase(const FloatingModel& model,
                                                  const std::vector<SensorSet>& sets,
                                                  const FloatingStructuralOptions& options) {
  options.structural.check();
  if (options.motion == FloatingMotion::kHolding && options.contacts.empty())
    throw InputError("a robot that holds contacts (`motion` holding) needs its `contacts`");
  if (options.motion == FloatingMotion::kFree &&
      std::find(sets.begin(), sets.end(), SensorSet::kWrenches) != sets.end())
    throw InputError(
        "in flight (`motion` free) nothing carries a wrench: the sensor set "
        "wrenches measures zero, which fixes no parameter's scale; analyse it holding "
        "contacts or suspended");
  const int p = model.numParameters();
  const int samples = options.structural.samples > 0 ? options.structural.samples
                                                     : std::max(100, 5 * p / model.numVelocities());
  FloatingStateSampler sampler(model, options);
  std::vector<RandomState> states;
  for (int k = 0; k < samples; ++k) {
    const FloatingState state = sampler.next();
    states.push_back({sampler.regressor(state), sampler.jacobian(state)});
  }
  const std::vector<std::string> names = floatingParameterNames(model);
  const std::vector<int> preference = floatingPreference(model);
  std::vector<SensorSetBase> out;
  for (SensorSet set : sets) {
    std::vector<Eigen::MatrixXd> blocks;
    Eigen::Index rows = 0;
    for (const RandomState& state : states) {
      blocks.push_back(sensorRows(set, state.Y, state.J));
      rows += blocks.back().rows();
    }
    Eigen::MatrixXd W(rows, p);
    rows = 0;
    for (const Eigen::MatrixXd& b : blocks) {
      W.middleRows(rows, b.rows()) = b;
      rows += b.rows();
    }
    SensorSetBase entry;
    entry.set = set;
    entry.base = computeBaseParameters(W, names, options.structural.tolerance, preference);
    entry.determined_alone = determinedAlone(entry.base);
    out.push_back(std::move(entry));
  }
  return out;
}

}  // namespace dynid
