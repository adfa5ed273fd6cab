// Simulated measurements of a floating robot (docs/FLOATING.md): random states of a motion class
// (identifiability/floating/sensor_sets.hpp's FloatingStateSampler), the joint torques and contact
// forces inverse dynamics needs there, noise on every measured channel.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/controllers.hpp"
#include "data/floating/floating_dataset.hpp"
#include "identifiability/floating/floating_fit.hpp"

namespace dynid {

struct FloatingSimulationOptions {
  int samples = 200;
  std::uint64_t seed = 1;
  FloatingMotion motion = FloatingMotion::kHolding;
  std::vector<Contact> contacts;
  double torque_noise = 0.0;  // sd of each joint torque [N m]
  double force_noise = 0.0;   // sd of each contact force component [N]
  double moment_noise = 0.0;  // sd of each frame contact's moment component [N m]
  /// The joints follow this design (`dynid excite` of the robot with its base fixed) instead of
  /// random states: `samples` states evenly over one period, the base held still (the suspended
  /// motion only: a robot on a stand or hung from its sensor). Unset: random states.
  std::optional<FourierSeries> trajectory;
  /// With `trajectory`: the stand's orientations, each a (roll, pitch) [rad] (rotationFromRpy,
  /// yaw 0), the design simulated once at each in turn (`samples` states each), each run after
  /// the one before it by the period and a 1 s gap (no segment of a rollout crosses it): a stand
  /// tilted between recordings, which shows the whole body's first moment along gravity that one
  /// orientation cannot. Empty: upright only. At most kMaxStandTilts, each finite.
  std::vector<Eigen::Vector2d> stand_tilts;
  /// The friction coefficient mu of the ground under the holding contacts: their forces are the
  /// least-norm ones within cones of half-angle atan(mu) about the ground's normal (against
  /// gravity; a frame contact's force, its moment free), and a random state they cannot hold is
  /// drawn again. 0: the least-norm forces, no cones (a contact may pull). Holding motion only.
  double friction_cone = 0.0;
  /// A flat sole under every frame contact that holds: its corners (x, y) in the frame's x-y
  /// plane [m], three or more, not all on one line (rectangularSole for a rectangle centred at
  /// the frame's origin; an ankle frame behind a sole's middle, a foot's outline). The contact's
  /// wrench is then that of forces at the corners, each within the cone of `friction_cone` about
  /// the sole's normal (the frame's z: the ground under a sole lies along it), least-norm: the
  /// centre of pressure stays in the corners' convex hull (the support polygon) and the moment
  /// about the normal within what friction gives. Empty: a frame contact's moment free. Needs
  /// friction_cone and a frame contact.
  std::vector<Eigen::Vector2d> sole;
  /// The robot moves as this dataset says, sample by sample (a recording's prepared motion,
  /// another simulator's: its time, base orientation, twist and acceleration, q, dq and ddq; its
  /// torques and wrenches are not read) instead of random states; `samples` is its count. Holding:
  /// each contact holds where the dataset's flag at its frame says (every contact needs one;
  /// no `contacts`: the dataset's flagged frames, a frame contact where it has a six-component
  /// wrench, a point otherwise); suspended and carried: the base's support carries it. A sample
  /// whose base wrench no forces within the friction cones carry gets the least-norm forces
  /// (FloatingSimulation::outside_cones). Not with `trajectory` or in flight.
  std::shared_ptr<const FloatingDataset> motion_from;
};

/// The most stand orientations one simulation takes (FloatingSimulationOptions::stand_tilts), and
/// the most samples (FloatingSimulationOptions::samples; a design's at each orientation).
inline constexpr int kMaxStandTilts = 16;
inline constexpr int kMaxFloatingSamples = 1000000;

/// A rectangle's corners, length along x and width along y, centred at the origin (a sole for
/// FloatingSimulationOptions::sole). Throws InputError (naming `sole`) unless both are positive
/// and finite.
std::vector<Eigen::Vector2d> rectangularSole(double length, double width);

/// The samples, and the noise variances they were drawn with (for generalized least squares).
struct FloatingSimulation {
  std::vector<FloatingMeasurement> samples;
  Eigen::VectorXd torque_variance;
  /// The states drawn: the samples and those the cones could not hold (`friction_cone`).
  int drawn = 0;
  /// With `motion_from`: the samples whose base wrench no forces within the cones carry (a pull or
  /// a slide), given the least-norm forces instead.
  std::vector<int> outside_cones;
  /// With `motion_from`: the samples whose base wrench the holding contacts cannot carry at all
  /// (their Jacobian's base columns of rank < 6, as two point feet, or none holding while the
  /// motion needs a wrench), given the least-squares forces: there the floating equations do not
  /// hold.
  std::vector<int> unsupported;
};

/// Measurements of `model` (its own parameters are the truth) in states of the options' motion
/// (a design: see FloatingSimulationOptions::trajectory; InputError naming `trajectory` for another
/// motion than suspended or a design of another joint count):
///   holding    the active contacts carry the base wrench inverse dynamics needs, by the
///              least-norm forces (within friction cones with `friction_cone`: contact_forces.hpp),
///              the joints the rest;
///   suspended  the base's support carries it (measured as a frame contact at the base origin);
///   carried    the base moves as its support drives it, the support's wrench measured as
///              suspended's;
///   free       nothing holds: FloatingStateSampler::flight (the forward dynamics' accelerations
///              with no wrench on the base).
/// Throws InputError as FloatingStateSampler does, and naming `friction_cone` (negative or not
/// finite; with another motion than holding; a model without gravity; no state held in 200 draws).
FloatingSimulation simulateFloating(const FloatingModel& model,
                                    const FloatingSimulationOptions& options);

/// The same measurements as a dataset (data/floating/floating_dataset.hpp), one state a row
/// (time a sample index at 0.01 s: the states are independent draws, not a trajectory; with a
/// design, the design's time over its period; with a given motion, its time): the base
/// motion and joint states exact, the torques, and per contact its wrench in its frame's axes (a
/// contact that does not hold reads noise about zero) and its flag; suspended and carried add the
/// base's support as a frame contact at the base link. Noise as simulateFloating's; `drawn`,
/// `outside_cones` and `unsupported`, when given, receive FloatingSimulation's.
FloatingDataset simulateFloatingDataset(const FloatingModel& model,
                                        const FloatingSimulationOptions& options,
                                        int* drawn = nullptr,
                                        std::vector<int>* outside_cones = nullptr,
                                        std::vector<int>* unsupported = nullptr);

/// What a simulation along a given motion says of the samples it could not give forces within the
/// cones (`outside_cones`) or at all (`unsupported`), with their count and the first one's time in
/// `simulated`; empty when there are none.
std::vector<std::string> givenMotionWarnings(const FloatingDataset& simulated,
                                             const std::vector<int>& outside_cones,
                                             const std::vector<int>& unsupported);

}  // namespace dynid
