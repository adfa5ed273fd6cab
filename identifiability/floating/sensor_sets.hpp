// What a floating-base robot's sensors can determine (docs/FLOATING.md): the rows each sensor set
// gives, and the structural base parameters of each set.
//
// The floating equations of motion are Y(base, q, dq, ddq) theta = (w, tau): six base rows, whose
// right side w is the sum of the contact wrenches about the base origin (no joint torque enters
// them), and n joint rows. A sensor set keeps what its sensors measure:
//   wrenches          the six base rows, w from force-torque sensors or force plates; no joint
//                     torque, so no drive term (friction acts between links);
//   torques_wrenches  every row: joint torques and the contact wrenches;
//   torques_contacts  joint torques and which contacts hold (flags), not their forces: with J the
//                     active contacts' stacked Jacobian, Y theta = (0, tau) + J^T lambda for
//                     unknown contact forces lambda, eliminated by an orthonormal basis N of J's
//                     null space: N^T Y theta = N^T (0, tau).
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "core/floating/contact_jacobian.hpp"
#include "identifiability/base_parameters.hpp"

namespace dynid {

enum class SensorSet { kWrenches, kTorquesAndWrenches, kTorquesAndContactFlags };
inline constexpr SensorSet kSensorSets[] = {SensorSet::kWrenches, SensorSet::kTorquesAndWrenches,
                                            SensorSet::kTorquesAndContactFlags};

/// "wrenches", "torques_wrenches" or "torques_contacts".
const char* sensorSetName(SensorSet set);
/// One sentence: what the set measures.
const char* sensorSetDescription(SensorSet set);
/// The set of a name (sensorSetName's). Throws InputError naming `sensors` and the names.
SensorSet parseSensorSet(std::string_view text);

/// The rows one sample gives to `set`, from the floating regressor Y ((6 + n) x p) and the active
/// contacts' stacked Jacobian (k x (6 + n), k >= 0; read by torques_contacts only). Throws
/// InputError when the sizes disagree.
Eigen::MatrixXd sensorRows(SensorSet set, const Eigen::MatrixXd& Y,
                           const Eigen::MatrixXd& contact_jacobian);
/// The measurements those rows equal, from the joint torques tau (n, the drives' output) and the
/// active contacts' forces lambda (stacked as the Jacobian's rows: each a force, or a wrench (n, f)
/// about its frame's origin, in base-frame axes): wrenches (J^T lambda)'s six base entries, the
/// base wrench; torques_wrenches (0, tau) + J^T lambda; torques_contacts N^T (0, tau), lambda
/// unused. Throws InputError when the sizes disagree.
Eigen::VectorXd sensorMeasurements(SensorSet set, const Eigen::VectorXd& tau,
                                   const Eigen::MatrixXd& contact_jacobian,
                                   const Eigen::VectorXd& contact_forces);

/// How the robot moves in the data an analysis is for:
///   holding    a random subset of the contacts holds in each state (standing, walking; the
///              default; needs contacts): the motion keeps those contact points still;
///   free       nothing holds (a robot in flight): no wrench on the base, the motion the forward
///              dynamics gives (the sensor set wrenches then measures zero and is refused);
///   suspended  the base is held still (hung from a force-torque sensor, or on a stand): its twist
///              and acceleration zero; for torques_contacts the support's wrench is unknown and
///              eliminated like a contact's;
///   carried    the base is moved by a support that carries it (a mobile platform, a motion
///              stand, a crane or an arm holding the robot): the base moves as it is driven (any
///              twist and acceleration), the support's wrench at the base's origin measured for
///              the wrench sets and eliminated for torques_contacts, as suspended's.
enum class FloatingMotion { kHolding, kFree, kSuspended, kCarried };
/// "holding", "free", "suspended", "carried".
const char* floatingMotionName(FloatingMotion motion);
/// Throws InputError naming `motion` and the names.
FloatingMotion parseFloatingMotion(std::string_view text);

/// The structural analysis of a floating robot: StructuralOptions' samples (0: max(100,
/// 5 p / (6 + n))), seed and tolerance, the contacts and the motion. Every sensor set is analysed
/// on the same states, so that their counts compare.
struct FloatingStructuralOptions {
  StructuralOptions structural;
  std::vector<Contact> contacts;
  FloatingMotion motion = FloatingMotion::kHolding;
};

/// A state of a floating robot: the base's motion, the joints', which contacts hold (indices into
/// the options' contacts) and whether the base itself is held (suspended, carried: a support's
/// wrench acts on it).
struct FloatingState {
  BaseMotion base;
  Eigen::VectorXd q, dq, ddq;
  std::vector<int> active;
  bool base_held = false;
};

/// Random states from the options' seed: uniform base orientations, q within the limits (or
/// +-pi, +-1 m); velocities and accelerations as each draw says.
class FloatingStateSampler {
 public:
  /// Keeps references to both: they must outlive the sampler.
  FloatingStateSampler(const FloatingModel& model, const FloatingStructuralOptions& options);
  /// Any motion (twist and rates within +-1 and +-2, accelerations +-3 and +-5): the contacts'
  /// wrenches are measured, so nothing constrains it.
  FloatingState generic();
  /// A motion in which a random subset of the contacts holds, one that can carry any base wrench
  /// (the active Jacobian's base columns of rank 6, so the robot can be in this state whatever its
  /// parameters): velocities in the null space of the active contacts' Jacobian J, accelerations
  /// with J a + (dJ/dt) v = 0, the contact points still (dJ/dt v by central differences of J along
  /// dq, h = 1e-6: ~1e-12 relative, far below the rank rule's 1e-8). Throws InputError when no
  /// subset reaches rank 6 in 200 draws (point feet of a biped: two points).
  FloatingState holding();
  /// The base held still (twist and acceleration zero), the joints anywhere.
  FloatingState suspended();
  /// The base moved by its support: generic()'s motion, the support's wrench acting on the base.
  FloatingState carried();
  /// In flight: generic()'s configuration and velocities, joint torques drawn within +-10 N m and
  /// the accelerations the forward dynamics gives with no wrench on the base (the model's own
  /// parameters: a state the robot can be in).
  FloatingState flight();
  /// The options' motion: holding(), flight(), suspended() or carried().
  FloatingState next();
  /// What holds at the state, as one Jacobian: the active contacts' stacked, and the base's
  /// own (identity on the base twist) when it is held; no rows in flight.
  Eigen::MatrixXd jacobian(const FloatingState& state);
  /// The floating regressor at a state.
  Eigen::MatrixXd regressor(const FloatingState& state);

 private:
  double uniform(double half);
  Eigen::VectorXd randomVector(int size, double half);
  FloatingState configuration();
  void setMotion(FloatingState& state, const Eigen::VectorXd& v, const Eigen::VectorXd& a);
  Eigen::MatrixXd contactRows(const std::vector<int>& active, const Eigen::VectorXd& q);

  const FloatingModel& model_;
  const FloatingStructuralOptions& options_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::normal_distribution<double> normal_{0.0, 1.0};
  FloatingData data_;
};

/// One sensor set's structural base parameters, and the standard parameters it determines alone
/// (each one's unit vector in the row space: orthogonal to the null space within 1e-9).
struct SensorSetBase {
  SensorSet set = SensorSet::kTorquesAndWrenches;
  BaseParameters base;
  std::vector<int> determined_alone;
};

/// Every requested set from the same seeded random states (FloatingStateSampler::next), so their
/// counts compare: the rows of wrenches and of torques_contacts lie in those of torques_wrenches,
/// and the difference of counts is what the added sensor brings. Throws InputError for holding
/// without contacts, a contact on a body the model lacks, or options out of range.
std::vector<SensorSetBase> floatingStructuralBase(const FloatingModel& model,
                                                  const std::vector<SensorSet>& sets,
                                                  const FloatingStructuralOptions& options = {});

/// The default preference for a floating layout: the base body as a link before link 1, then
/// defaultPreference's order.
std::vector<int> floatingPreference(const FloatingModel& model);

}  // namespace dynid
