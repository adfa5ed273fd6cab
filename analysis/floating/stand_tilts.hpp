// The floating wing (analysis/floating/, floor 3): floating-base robots' command family. This room:
// the orientations of a stand on which a suspended robot runs a joint design (`dynid excite
// --stands K`, docs/FLOATING.md "Choosing a stand's tilts").
//
// A base that never tilts sees gravity from one side: its support's six rows (the wrenches set)
// cannot show the whole body's first moment along gravity, and the joint torques see the limbs'
// gravity from that side only. Recording the design at several stand orientations shows what one
// cannot; which orientations is an experiment design question. The criterion is the wrenches
// set's, the support's six rows a state: the unit-column condition number of their base
// regressor over the design at every chosen orientation (its information matrix is the sum of
// each orientation's, so a candidate's worth is its information added to the rest).
#pragma once

#include <limits>
#include <vector>

#include <Eigen/Core>

#include "core/controllers.hpp"
#include "identifiability/floating/sensor_sets.hpp"

namespace dynid {

/// The most orientations a choice may have (as many as a simulation takes: simulate.hpp's
/// kMaxStandTilts, restated here so that this room reads without it).
inline constexpr int kMaxStandChoices = 16;

struct StandTiltRequest {
  /// The joints' design (`dynid excite` of the robot with its base fixed), run at each orientation.
  FourierSeries design;
  /// Orientations to choose, 1 to kMaxStandChoices: the first is the stand upright (as built), the
  /// others chosen in turn (greedy), then each exchanged for a better candidate while one is.
  int stands = 3;
  /// The candidates: roll and pitch each on `tilt_grid` points evenly over [-max_tilt, max_tilt]
  /// [rad] (yaw leaves gravity's direction in the base frame as it is). max_tilt in (0, pi/2];
  /// tilt_grid odd, 3 to 21, so upright is a candidate.
  double max_tilt = 0.4;
  int tilt_grid = 9;
  /// States of the design at each orientation (evenly over its period), 10 to 10000.
  int samples = 200;
  /// The structural analysis' samples, seed and tolerance (the base parameters the rows are read
  /// in; the suspended motion class).
  StructuralOptions structural;
  /// Throws InputError naming the first field out of its range.
  void check() const;
};

/// One sensor set on the design at some orientations.
struct StandSetScore {
  SensorSet set = SensorSet::kWrenches;
  int combinations = 0;  // the set's structural base parameters (a suspended robot)
  int determined = 0;    // those the design's rows excite (the rank rule: 1e-8)
  double condition = std::numeric_limits<double>::infinity();  // unit-column; inf below full rank
};

struct StandTiltChoice {
  std::vector<Eigen::Vector2d> tilts;  // (roll, pitch) [rad], upright first
  /// The criterion after each orientation was added (greedy order, before the exchanges), and at
  /// the end.
  std::vector<double> condition_added;
  double condition = std::numeric_limits<double>::infinity();
  int candidates = 0, exchanges = 0;
  std::vector<StandSetScore> upright;  // every set, the design upright alone
  std::vector<StandSetScore> chosen;   // every set, the design at the chosen orientations
};

/// Chooses the orientations (deterministic: no draw but the structural analysis', from its seed).
/// Throws InputError for a request out of range or a design whose joint count is not the model's.
StandTiltChoice chooseStandTilts(const FloatingModel& model, const StandTiltRequest& request);

/// Every set's determined count and condition number on the request's design at the given
/// orientations (the request's stands, max_tilt and tilt_grid unread): tilts chosen by hand, scored
/// as a choice is. Throws InputError as chooseStandTilts, or for no tilt.
std::vector<StandSetScore> scoreStandTilts(const FloatingModel& model,
                                           const StandTiltRequest& request,
                                           const std::vector<Eigen::Vector2d>& tilts);

}  // namespace dynid
