// The floating wing (analysis/floating/, floor 3): a standing robot's sway designed for
// identification (`dynid excite --floating-base --contacts FEET --stance Q`, docs/FLOATING.md
// "Designing a standing sway").
//
// A robot that stands cannot move its joints at will: its feet stay where the stance puts them,
// so the joints follow the base (standing.hpp). What the experiment chooses is the base's motion:
// each of its six coordinates (x, y, z, roll, pitch, yaw) a periodic Fourier series that starts
// and ends at rest at the stance, optimised (COBYLA, multistart) for the unit-column condition
// number of one sensor set's base regressor over the motion, within bounds on the sway and the
// turn, the joints' limits (with a margin) and velocity limits, and with friction cones, forces
// that the feet can carry without slipping.
//
// What a standing robot's motions can determine at all is less than what its holding states can
// (four feet of a quadruped fixed in the world tie its legs' motion to the base's): the criterion
// is read in the standing class, the holding class's base parameters that the rows of random sways
// of the same stance pooled excite, by identify's rank rule (the design's own rows pooled in at
// the end).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/controllers.hpp"
#include "core/floating/contact_jacobian.hpp"
#include "core/run_control.hpp"
#include "identifiability/floating/sensor_sets.hpp"

namespace dynid {

struct StandingDesignRequest {
  /// The feet (soles) that hold throughout, and the joints at rest (standing.hpp's).
  std::vector<Contact> contacts;
  Eigen::VectorXd stance;
  /// The sensor set whose condition number the design lowers (every set is scored).
  SensorSet set = SensorSet::kTorquesAndContactFlags;
  double period = 4.0;  // [s], 0.5 to 120
  int harmonics = 3;    // per coordinate, 2 to 10 (rest at t = 0 takes two)
  /// Bounds on the base's excursion from the stance: each world axis [m], each of roll, pitch and
  /// yaw [rad]; both positive and finite (up to 1 m and pi/4).
  double max_sway = 0.04;
  double max_turn = 0.15;
  /// The largest excursion from the stance of each joint no foot depends on (a humanoid's arms,
  /// head and trunk), which the design moves too [rad], 0 (they stay at the stance) to pi.
  double max_swing = 0.3;
  /// The joints stay this far inside their position limits [rad], 0 or more.
  double joint_margin = 0.05;
  /// The feet's friction coefficient: the least-norm forces that hold the motion stay within its
  /// cones about the ground's normal at every sample (so `dynid simulate --friction-cone` never
  /// needs another split); 0 imposes none.
  double friction_cone = 0.0;
  /// A flat sole under every frame contact (`dynid simulate --sole`'s corners in the frame's x-y
  /// plane [m]; empty: none): the least-norm wrench that holds each sample keeps each frame
  /// contact's centre of pressure in the corners' convex hull. 3 to 32 corners enclosing an area.
  std::vector<Eigen::Vector2d> sole;
  double grid_rate = 10.0;    // samples per second of the optimiser's criterion and bounds
  double check_rate = 100.0;  // samples per second of the final check and the scores
  int starts = 4;             // 1 to 64, seeded: start k's draw depends on `seed` and k only
  int evaluations = 300;      // COBYLA evaluations per start, 10 to 100000
  double max_seconds = std::numeric_limits<double>::infinity();  // the whole design
  /// The holding class's structural analysis (samples, seed, tolerance); the standing class is read
  /// by identify's rule, not this tolerance.
  StructuralOptions structural;
  std::uint64_t seed = 1;
  RunControl control;
  /// Throws InputError naming the first field out of its range.
  void check() const;
};

/// One sensor set on a standing motion.
struct StandingSetScore {
  SensorSet set = SensorSet::kTorquesAndContactFlags;
  int holding = 0;     // the set's structural base parameters, the robot holding on the contacts
  int standing = 0;    // those any sway of this stance can determine (the standing class)
  int determined = 0;  // those this motion's rows excite (the rank rule: 1e-8)
  double condition = std::numeric_limits<double>::infinity();  // unit-column, standing class
};

struct StandingDesign {
  /// The base's six coordinates (standing.hpp's StandingMotionRequest::base_design): rest and the
  /// stance's pose at t = 0.
  FourierSeries base;
  /// The joints no foot depends on (StandingMotionRequest::joint_design: n rows, those of the
  /// joints a foot depends on unread), at the stance at rest at t = 0; none when no joint is free
  /// or `max_swing` is 0.
  std::optional<FourierSeries> joints;
  std::vector<StandingSetScore> scores;  // every set, the design at check_rate over one period
  /// Every set on `dynid simulate --stance`'s default sway over the same period, or empty with
  /// the reason when its legs cannot follow it from this stance.
  std::vector<StandingSetScore> baseline;
  std::string baseline_problem;
  /// The design at check_rate: the largest excursion along an axis [m] and about one [rad], the
  /// smallest distance of a joint to its limits [rad], and the largest share of the cone a foot's
  /// force uses (|tangential| / (mu normal); 0 without cones), and the smallest distance of a
  /// centre of pressure to its sole's edge [m] (infinity without a sole).
  double largest_sway = 0.0, largest_turn = 0.0, joint_clearance = 0.0, cone_use = 0.0;
  double largest_swing = 0.0;  // the free joints' largest excursion from the stance [rad]
  double sole_clearance = std::numeric_limits<double>::infinity();
  double shrink = 1.0;                   // the factor on the coefficients that made the check pass
  std::vector<double> start_objectives;  // log10 of each start's best feasible criterion; NaN: none
  int best_start = -1;
  long evaluations = 0;
  std::string termination;  // "evaluations", "seconds" or "interrupted"
  double seconds = 0.0;
};

/// Designs the sway. Throws InputError for a request out of range or that does not fit the model
/// (the stance's size, a contact it lacks), when the stance leaves no room to sway (no random sway
/// of a tenth of the bounds can be followed) and Error when no start meets the bounds.
StandingDesign designStandingSway(const FloatingModel& model, const StandingDesignRequest& request);

}  // namespace dynid
