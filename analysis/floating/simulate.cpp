#include "analysis/floating/simulate.hpp"

#include <cmath>
#include <random>
#include <utility>

#include "analysis/floating/contact_forces.hpp"
#include "analysis/floating/identifiability.hpp"
#include "core/errors.hpp"
#include "core/floating/contact_jacobian.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/format.hpp"
#include "core/spatial.hpp"

namespace dynid {

namespace {
/// Each force row's noise sd: a point contact's three forces, a frame contact's three moments
/// then three forces; the held base's (suspended, carried) six rows come first, a frame's.
Eigen::VectorXd forceSd(const FloatingState& state, const FloatingSimulationOptions& o) {
  std::vector<double> sd;
  const auto frame = [&] {
    for (int k = 0; k < 3; ++k) sd.push_back(o.moment_noise);
    for (int k = 0; k < 3; ++k) sd.push_back(o.force_noise);
  };
  if (state.base_held) frame();
  for (int c : state.active) {
    if (o.contacts[static_cast<std::size_t>(c)].kind == Contact::Kind::kFrame)
      frame();
    else
      for (int k = 0; k < 3; ++k) sd.push_back(o.force_noise);
  }
  return Eigen::Map<Eigen::VectorXd>(sd.data(), static_cast<Eigen::Index>(sd.size()));
}
FloatingStructuralOptions samplingOf(const FloatingSimulationOptions& o) {
  FloatingStructuralOptions sampling;
  sampling.structural.seed = o.seed;
  sampling.contacts = o.contacts;
  sampling.motion = o.motion;
  return sampling;
}

/// A state and what holds it: the Jacobian of what holds, the generalized force inverse dynamics
/// needs there (base wrench, joint torques) and the holding contacts' forces (the Jacobian's rows).
struct HeldState {
  FloatingState state;
  Eigen::MatrixXd J;
  Eigen::VectorXd generalized, forces;
};

/// The cones of a state's holding contacts: each point contact's force, each frame contact's force
/// after its moment; the ground's normal against gravity, in the base's axes.
ContactCones conesOf(const FloatingModel& model, const FloatingSimulationOptions& o,
                     const FloatingState& state) {
  ContactCones cones;
  cones.friction = o.friction_cone;
  cones.up = -(state.base.rotation.transpose() * model.gravity()).normalized();
  int row = 0;
  for (int c : state.active) {
    const bool frame = o.contacts[static_cast<std::size_t>(c)].kind == Contact::Kind::kFrame;
    cones.coned.push_back(frame ? row + 3 : row);
    row += frame ? 6 : 3;
  }
  return cones;
}

/// The base wrench's split among the holding contacts (J's rows: a point's force, a frame's moment
/// about its origin then its force, in the base's axes), within the cones: conesOf's, or with a
/// sole each frame contact's wrench that of the forces at its sole's corners, each coned
/// about the sole's normal (FloatingSimulationOptions::sole). nullopt when they cannot carry it.
std::optional<Eigen::VectorXd> holdingForces(const FloatingModel& model, FloatingData& data,
                                             const FloatingSimulationOptions& o,
                                             const FloatingState& state, const Eigen::MatrixXd& J,
                                             const Eigen::VectorXd& wrench) {
  const Eigen::MatrixXd map = J.leftCols<6>().transpose();
  const ContactCones cones = conesOf(model, o, state);
  if (o.sole.empty()) return contactForces(map, wrench, cones);
  // The unknowns (3 a point, 3 a sole's corner) and E, the map from them to J's rows.
  const auto isFrame = [&](int c) {
    return o.contacts[static_cast<std::size_t>(c)].kind == Contact::Kind::kFrame;
  };
  Eigen::Index unknowns = 0;
  const auto corners_count = static_cast<Eigen::Index>(o.sole.size());
  for (int c : state.active) unknowns += isFrame(c) ? 3 * corners_count : 3;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(J.rows(), unknowns);
  ContactCones corners;
  corners.friction = o.friction_cone;
  Eigen::Index row = 0, unknown = 0;
  for (int c : state.active) {
    if (!isFrame(c)) {
      E.block<3, 3>(row, unknown).setIdentity();
      corners.coned.push_back(static_cast<int>(unknown));
      corners.axes.push_back(cones.up);
      row += 3, unknown += 3;
      continue;
    }
    const Eigen::Matrix3d R =
        contactPose(model, data, o.contacts[static_cast<std::size_t>(c)], state.q).rotation;
    for (const Eigen::Vector2d& xy : o.sole) {
      const Eigen::Vector3d corner(xy.x(), xy.y(), 0.0);
      E.block<3, 3>(row, unknown) = skew(Eigen::Vector3d(R * corner));
      E.block<3, 3>(row + 3, unknown).setIdentity();
      corners.coned.push_back(static_cast<int>(unknown));
      corners.axes.push_back(R.col(2));
      unknown += 3;
    }
    row += 6;
  }
  const std::optional<Eigen::VectorXd> x = contactForces(map * E, wrench, corners);
  if (!x) return std::nullopt;
  return Eigen::VectorXd(E * *x);
}

/// The most corners a sole may have: each adds three unknowns to every draw's cone solve (up to
/// 2000 draws a sample), so a list of thousands would run for hours.
constexpr std::size_t kMaxSoleCorners = 32;

/// Whether the corners span an area: some corner off the line through the first and the one
/// farthest from it (beyond round-off of that distance squared).
bool enclosesArea(const std::vector<Eigen::Vector2d>& corners) {
  Eigen::Vector2d far = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& c : corners)
    if ((c - corners[0]).squaredNorm() > far.squaredNorm()) far = c - corners[0];
  for (const Eigen::Vector2d& c : corners) {
    const Eigen::Vector2d d = c - corners[0];
    if (std::abs(far.x() * d.y() - far.y() * d.x()) > 1e-9 * far.squaredNorm()) return true;
  }
  return false;
}

/// Draws a state within the cones can hold this many times before giving up on a sample; with
/// soles, ten times as many (3 % of Romeo's random holding states stand on soles of 0.2 x 0.1 m at
/// mu 0.8, measured: 309 draws for 10 samples).
constexpr int kDrawsPerSample = 200, kDrawsPerSampleOnSoles = 2000;

/// What both simulations draw with: the seeded states of the options' motion (or the design's,
/// in order), a workspace and the noise's generator.
struct Draws {
  Draws(const FloatingModel& m, const FloatingSimulationOptions& o)
      : model(m),
        sampling(samplingOf(o)),
        sampler(m, sampling),
        data(m),
        rng(o.seed ^ 0x5eed),
        options(o) {
    checkFriction();
    checkGivenMotion();
    checkTilts();
    if (!o.trajectory) return;
    if (o.motion != FloatingMotion::kSuspended)
      throw InputError(
          "`trajectory`: a designed motion is simulated on a suspended robot (its base "
          "held still), not " +
          std::string(floatingMotionName(o.motion)));
    if (o.trajectory->numJoints() != m.numJoints())
      throw InputError("`trajectory` moves " + std::to_string(o.trajectory->numJoints()) +
                       " joints; the robot has " + std::to_string(m.numJoints()));
  }
  void checkFriction() const {
    if (!(options.friction_cone >= 0.0) || !std::isfinite(options.friction_cone))
      throw InputError("`friction_cone` must be a finite coefficient >= 0 (0: no cones), not " +
                       formatNumber(options.friction_cone));
    checkSole();
    if (options.friction_cone == 0.0) return;
    if (options.motion != FloatingMotion::kHolding)
      throw InputError(
          "`friction_cone`: cones bound the forces of contacts on the ground (the holding "
          "motion), not " +
          std::string(floatingMotionName(options.motion)));
    if (model.gravity().norm() == 0.0)
      throw InputError(
          "`friction_cone`: the cones stand on the ground's normal, against gravity, "
          "and this model has none");
  }
  /// The given motion's flags, one per contact (holding), checked against the options.
  void checkGivenMotion() {
    if (!options.motion_from) return;
    const FloatingDataset& d = *options.motion_from;
    if (options.trajectory)
      throw InputError("`motion_from` and `trajectory` are two motions: give one");
    if (options.motion == FloatingMotion::kFree)
      throw InputError(
          "`motion_from`: a given motion is simulated holding its contacts, suspended or "
          "carried, not free (in flight its accelerations would have to be the forward "
          "dynamics')");
    if (d.q.rows() != model.numJoints())
      throw InputError("`motion_from` moves " + std::to_string(d.q.rows()) +
                       " joints; the robot has " + std::to_string(model.numJoints()));
    if (options.motion != FloatingMotion::kHolding) return;
    if (options.contacts.empty())
      throw InputError("`motion_from`: " + where(d) +
                       " has no contact flag and `contacts` is empty: nothing holds the robot "
                       "(give them, or `motion` suspended or carried)");
    for (const Contact& c : options.contacts) {
      const FloatingDataset::Flag* flag = d.findFlag(c.name);
      if (flag == nullptr)
        throw InputError("`motion_from`: " + where(d) + " has no flag for the contact at " +
                         c.name + " (column contact:" + c.name +
                         "): a given motion says when each contact holds");
      flags.push_back(flag);
    }
  }
  static std::string where(const FloatingDataset& d) {
    return d.file.empty() ? std::string("the dataset") : "'" + d.file + "'";
  }
  /// Sample k of the given motion, holding where its flags say.
  FloatingState given(int k) const {
    const FloatingDataset& d = *options.motion_from;
    FloatingState s;
    s.base.rotation = baseRotation(Eigen::Vector4d(d.orientation.col(k)));
    s.base.twist = d.twist.col(k);
    s.base.acceleration = d.acceleration.col(k);
    s.q = d.q.col(k), s.dq = d.dq.col(k), s.ddq = d.ddq.col(k);
    s.base_held = options.motion != FloatingMotion::kHolding;
    for (std::size_t c = 0; c < flags.size(); ++c)
      if (flags[c]->holding[static_cast<std::size_t>(k)] != 0)
        s.active.push_back(static_cast<int>(c));
    return s;
  }
  int samples() const {
    return options.motion_from ? options.motion_from->numSamples() : options.samples * runs();
  }
  /// The design's runs: one a stand orientation (at least the upright one).
  int runs() const {
    return options.trajectory ? std::max<int>(1, static_cast<int>(options.stand_tilts.size())) : 1;
  }
  /// The samples asked (not with a given motion: its own) and the stand tilts.
  void checkTilts() const {
    if (!options.motion_from && (options.samples < 1 || options.samples > kMaxFloatingSamples))
      throw InputError("`samples` is 1 to " + std::to_string(kMaxFloatingSamples) + ", not " +
                       std::to_string(options.samples));
    const std::vector<Eigen::Vector2d>& tilts = options.stand_tilts;
    if (tilts.empty()) return;
    if (!options.trajectory)
      throw InputError("`stand_tilts` tilt the stand a design is simulated on: give `trajectory`");
    if (static_cast<int>(tilts.size()) > kMaxStandTilts)
      throw InputError("`stand_tilts`: " + std::to_string(tilts.size()) +
                       " orientations; at most " + std::to_string(kMaxStandTilts));
    for (std::size_t k = 0; k < tilts.size(); ++k)
      if (!tilts[k].allFinite())
        throw InputError("`stand_tilts`: orientation " + std::to_string(k + 1) + " is not finite");
  }
  void checkSole() const {
    const std::vector<Eigen::Vector2d>& sole = options.sole;
    if (sole.empty()) return;
    for (std::size_t k = 0; k < sole.size(); ++k)
      if (!sole[k].allFinite())
        throw InputError("`sole`: corner " + std::to_string(k + 1) + " is not finite (" +
                         formatNumber(sole[k].x()) + ", " + formatNumber(sole[k].y()) + ")");
    if (sole.size() > kMaxSoleCorners)
      throw InputError("`sole` has " + std::to_string(sole.size()) + " corners, more than " +
                       std::to_string(kMaxSoleCorners) +
                       " (each adds three unknowns to every state's force split; a foot's "
                       "outline needs a handful)");
    if (sole.size() < 3 || !enclosesArea(sole))
      throw InputError(
          "`sole` needs three or more corners not all on one line (a support "
          "polygon with an area), not " +
          std::to_string(sole.size()) + (sole.size() < 3 ? "" : " on a line"));
    if (options.friction_cone == 0.0)
      throw InputError("`sole`: a sole's corners push within friction cones; give `friction_cone`");
    for (const Contact& c : options.contacts)
      if (c.kind == Contact::Kind::kFrame) return;
    throw InputError(
        "`sole`: no frame contact among the `contacts` stands on a sole (a point "
        "contact has none)");
  }
  /// A state drawn, with the Jacobian of what holds it and the generalized force its motion needs
  /// (its forces zero until they are shared).
  HeldState dynamicsOf(FloatingState state) {
    ++drawn;
    HeldState held;
    held.state = std::move(state);
    held.J = sampler.jacobian(held.state);
    const FloatingState& s = held.state;
    held.generalized = floatingRnea(model, data, s.base, s.q, s.dq, s.ddq);
    held.forces = Eigen::VectorXd::Zero(held.J.rows());
    return held;
  }
  /// State k of the options' samples, with what holds it: a random state is drawn again while
  /// the cones cannot carry its base wrench (InputError naming `friction_cone` after
  /// kDrawsPerSample, or kDrawsPerSampleOnSoles).
  HeldState next(int k) {
    if (options.motion_from) return nextGiven(k);
    const int draws = options.sole.empty() ? kDrawsPerSample : kDrawsPerSampleOnSoles;
    for (int attempt = 0; attempt < draws; ++attempt) {
      HeldState held = dynamicsOf(draw(k));
      if (held.J.rows() == 0) return held;
      const std::optional<Eigen::VectorXd> forces = holdingForces(
          model, data, options, held.state, held.J, Eigen::VectorXd(held.generalized.head<6>()));
      if (forces) {
        held.forces = *forces;
        return held;
      }
    }
    throw InputError("`friction_cone`: in " + std::to_string(draws) +
                     " random states the contacts that hold could not carry the base wrench "
                     "within cones of mu " +
                     formatNumber(options.friction_cone) +
                     " (a larger coefficient, or more contacts)");
  }
  /// Sample k of the given motion with what holds it: the forces within the cones, else the
  /// least-norm ones (`outside`); where the holding contacts cannot carry the base wrench at all
  /// (their base columns of rank < 6, or none holds), the least-squares ones (`unsupported`).
  HeldState nextGiven(int k) {
    HeldState held = dynamicsOf(given(k));
    const FloatingState& s = held.state;
    const Eigen::VectorXd wrench = held.generalized.head<6>();
    const double tolerance = 1e-9 * held.generalized.norm();
    if (held.J.rows() == 0) {
      if (wrench.norm() > tolerance) unsupported.push_back(k);
      return held;
    }
    std::optional<Eigen::VectorXd> forces = holdingForces(model, data, options, s, held.J, wrench);
    const Eigen::MatrixXd map = held.J.leftCols<6>().transpose();
    if (!forces) {
      forces = contactForces(map, wrench, {});
      outside.push_back(k);
    }
    held.forces = *forces;
    if ((map * held.forces - wrench).norm() > tolerance) unsupported.push_back(k);
    return held;
  }
  FloatingState draw(int k) {
    if (options.motion_from) return given(k);
    if (!options.trajectory) return sampler.next();
    FloatingState state;
    state.base_held = true;  // twist and acceleration zero; the stand's orientation
    if (!options.stand_tilts.empty()) {
      const Eigen::Vector2d& tilt =
          options.stand_tilts[static_cast<std::size_t>(k / options.samples)];
      state.base.rotation = rotationFromRpy(tilt[0], tilt[1], 0.0);
    }
    const double period = options.trajectory->period;
    evaluateReference(*options.trajectory, period * (k % options.samples) / options.samples,
                      state.q, state.dq, state.ddq);
    return state;
  }
  /// Sample k's time: the design's, evenly over one period (each stand orientation's run after the
  /// one before it, the period and 1 s later), else an index at 0.01 s.
  double time(int k) const {
    if (options.motion_from) return options.motion_from->time[k];
    if (!options.trajectory) return 0.01 * k;
    const double period = options.trajectory->period;
    return (period + 1.0) * (k / options.samples) +
           period * (k % options.samples) / options.samples;
  }
  const FloatingModel& model;
  FloatingStructuralOptions sampling;  // before the sampler, which keeps a reference to it
  FloatingStateSampler sampler;
  FloatingData data;
  std::mt19937_64 rng;
  std::normal_distribution<double> normal{0.0, 1.0};
  const FloatingSimulationOptions& options;
  std::vector<const FloatingDataset::Flag*> flags;  // the given motion's, one per contact
  int drawn = 0;
  std::vector<int> outside;      // given samples outside the cones
  std::vector<int> unsupported;  // given samples whose base wrench nothing holding carries
};

/// The options with a given motion's contacts when none are named (holding): its flagged frames,
/// a frame contact where it has a six-component wrench, a point otherwise.
FloatingSimulationOptions withGivenContacts(const FloatingModel& model,
                                            const FloatingSimulationOptions& requested) {
  FloatingSimulationOptions out = requested;
  if (!out.motion_from || !out.contacts.empty() || out.motion != FloatingMotion::kHolding)
    return out;
  std::vector<std::string> specs;
  for (const FloatingDataset::Flag& flag : out.motion_from->flags) {
    const FloatingDataset::Wrench* w = out.motion_from->findWrench(flag.frame);
    specs.push_back(flag.frame + (w != nullptr && w->values.rows() == 6 ? ":frame" : ""));
  }
  out.contacts = contactsOf(model, specs);
  return out;
}
}  // namespace

std::vector<Eigen::Vector2d> rectangularSole(double length, double width) {
  if (!(length > 0.0 && width > 0.0 && std::isfinite(length) && std::isfinite(width)))
    throw InputError("`sole`: a rectangle's length and width are both positive and finite, not " +
                     formatNumber(length) + ", " + formatNumber(width));
  const double x = 0.5 * length, y = 0.5 * width;
  return {{-x, -y}, {x, -y}, {x, y}, {-x, y}};
}

FloatingSimulation simulateFloating(const FloatingModel& model,
                                    const FloatingSimulationOptions& requested) {
  const FloatingSimulationOptions options = withGivenContacts(model, requested);
  Draws draws(model, options);
  FloatingStateSampler& sampler = draws.sampler;
  const auto normal = [&draws] { return draws.normal(draws.rng); };
  const int n = model.numJoints();
  FloatingSimulation out;
  out.torque_variance = Eigen::VectorXd::Constant(n, options.torque_noise * options.torque_noise);
  for (int k = 0; k < draws.samples(); ++k) {
    HeldState held = draws.next(k);
    FloatingMeasurement m;
    m.J = std::move(held.J);
    m.Y = sampler.regressor(held.state);
    m.forces = std::move(held.forces);
    m.tau = held.generalized.tail(n);
    if (m.J.rows() > 0) m.tau -= m.J.rightCols(n).transpose() * m.forces;
    const Eigen::VectorXd sd = forceSd(held.state, options);
    m.force_variance = sd.cwiseProduct(sd);
    for (Eigen::Index r = 0; r < m.forces.size(); ++r) m.forces[r] += sd[r] * normal();
    for (int i = 0; i < n; ++i) m.tau[i] += options.torque_noise * normal();
    out.samples.push_back(std::move(m));
  }
  out.drawn = draws.drawn;
  out.outside_cones = draws.outside;
  out.unsupported = draws.unsupported;
  return out;
}

FloatingDataset simulateFloatingDataset(const FloatingModel& model,
                                        const FloatingSimulationOptions& requested, int* drawn,
                                        std::vector<int>* outside_cones,
                                        std::vector<int>* unsupported) {
  const FloatingSimulationOptions options = withGivenContacts(model, requested);
  Draws draws(model, options);
  FloatingData& data = draws.data;
  const auto normal = [&draws] { return draws.normal(draws.rng); };
  // The contacts the dataset measures: the options', and the base's support when suspended or
  // carried.
  std::vector<Contact> contacts = options.contacts;
  const bool supported =
      options.motion == FloatingMotion::kSuspended || options.motion == FloatingMotion::kCarried;
  if (supported) {
    Contact support;
    support.name = model.baseName();
    support.kind = Contact::Kind::kFrame;
    if (model.findFrame(support.name) == nullptr)
      throw InputError("the base link '" + support.name + "' is no frame of the model");
    contacts.insert(contacts.begin(), support);
  }
  const int n = model.numJoints(), N = draws.samples();
  FloatingDataset out;
  out.joints = model.limbs().joint_names;
  out.time.resize(N);
  for (int k = 0; k < N; ++k) out.time[k] = draws.time(k);
  out.orientation.resize(4, N);
  out.twist.resize(6, N);
  out.acceleration.resize(6, N);
  for (Eigen::MatrixXd* m : {&out.q, &out.dq, &out.ddq, &out.tau}) m->resize(n, N);
  for (const Contact& c : contacts) {
    out.wrenches.push_back({c.name, Eigen::MatrixXd::Zero(c.dimension(), N)});
    out.flags.push_back({c.name, std::vector<char>(static_cast<std::size_t>(N), 0)});
  }
  for (int k = 0; k < N; ++k) {
    const HeldState held = draws.next(k);
    const FloatingState& state = held.state;
    const Eigen::Quaterniond orientation(state.base.rotation);
    out.orientation.col(k) << orientation.w(), orientation.x(), orientation.y(), orientation.z();
    out.twist.col(k) = state.base.twist;
    out.acceleration.col(k) = state.base.acceleration;
    out.q.col(k) = state.q;
    out.dq.col(k) = state.dq;
    out.ddq.col(k) = state.ddq;
    const Eigen::MatrixXd& J = held.J;
    const Eigen::VectorXd& forces = held.forces;
    out.tau.col(k) = held.generalized.tail(n);
    if (J.rows() > 0) out.tau.col(k) -= J.rightCols(n).transpose() * forces;
    // The holding contacts' forces (J's rows: the support's, then the active ones') in each
    // contact's own axes.
    std::vector<int> holding = state.active;
    for (int& c : holding) c += supported ? 1 : 0;
    if (supported) holding.insert(holding.begin(), 0);
    Eigen::Index row = 0;
    for (int c : holding) {
      const Contact& contact = contacts[static_cast<std::size_t>(c)];
      const Eigen::Matrix3d R = contactPose(model, data, contact, state.q).rotation;
      Eigen::MatrixXd& w = out.wrenches[static_cast<std::size_t>(c)].values;
      if (contact.kind == Contact::Kind::kFrame) {
        w.col(k).head<3>() = R.transpose() * forces.segment<3>(row);
        row += 3;
      }
      w.col(k).tail<3>() = R.transpose() * forces.segment<3>(row);
      row += 3;
      out.flags[static_cast<std::size_t>(c)].holding[static_cast<std::size_t>(k)] = 1;
    }
    for (int j = 0; j < n; ++j) out.tau(j, k) += options.torque_noise * normal();
    for (FloatingDataset::Wrench& w : out.wrenches)
      for (Eigen::Index r = 0; r < w.values.rows(); ++r)
        w.values(r, k) +=
            (w.values.rows() == 6 && r < 3 ? options.moment_noise : options.force_noise) * normal();
  }
  if (drawn != nullptr) *drawn = draws.drawn;
  if (outside_cones != nullptr) *outside_cones = draws.outside;
  if (unsupported != nullptr) *unsupported = draws.unsupported;
  return out;
}

std::vector<std::string> givenMotionWarnings(const FloatingDataset& simulated,
                                             const std::vector<int>& outside_cones,
                                             const std::vector<int>& unsupported) {
  const auto counted = [&simulated](const std::vector<int>& samples) {
    return std::to_string(samples.size()) +
           " of the motion's samples (from t = " + formatNumber(simulated.time[samples.front()]) +
           " s)";
  };
  std::vector<std::string> out;
  if (!outside_cones.empty())
    out.push_back(counted(outside_cones) +
                  " need a contact to pull or slide: no forces within the cones carry their base "
                  "wrench; written with the least-norm forces");
  if (!unsupported.empty())
    out.push_back(counted(unsupported) +
                  " need a wrench the contacts holding there cannot carry (fewer than six "
                  "independent directions, e.g. two point feet, or none): written with the "
                  "least-squares forces, where the floating equations do not hold");
  return out;
}

}  // namespace dynid
