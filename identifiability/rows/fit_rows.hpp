// Which torque rows a least-squares fit takes, and the drive columns a filtered torque needs.
//
// At rest (|dq_j| within joint j's rest velocity, core/model.hpp) the drive terms that need
// sign(dq) (core/drive_terms.hpp, signed_by_velocity) are static friction: any torque within
// their limits that the other torques demand. Joint j's torque there is the rigid-body torque
// plus an unknown, so its row is left out of the fit: kept, its static torque would bias every
// parameter it correlates with (gravity above all) and the row says nothing the model predicts.
// Only a model with such a term leaves rows out: without one, the model's friction at rest is
// zero, and the row is what the model says.
//
// A log whose torque was low-pass filtered with a zero-phase filter F (dynid prepare) measures
// F[tau] = F[Y theta] = F[Y] theta. The smooth columns pass F nearly unchanged (Y(F[q]) ~ F[Y(q)]
// for motion well inside the pass band), but sign(dq) steps at every reversal and F spreads the
// step over the filter's length: Y(F[q], ...)'s step is where F[tau]'s is a ramp, and the fit
// bends the other parameters to explain the difference. So, "parallel filtering": the
// signed_by_velocity columns are replaced by F applied to their values on the dataset's
// velocities, run by run, and a row is left out within the filter's reach of a static sample
// (F spreads the unknown static torque that far; kFilterReachShare): one at rest, or one where
// the joint dwells, slow and hardly accelerating. A joint that sticks at a stop or a reversal
// for a while shows, filtered, only a creep near zero (1e-3 rad/s over 0.1 s on a simulated PUMA
// whose joint 1 sticks), not rest by its own velocity; a clean reversal accelerates through zero
// and keeps its rows (their friction is the filtered columns' step).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"

namespace dynid {

/// The zero-phase Butterworth low-pass a dataset's torque went through (prepare.json's
/// filter.order and filter.tau_cutoff_hz; its rate is the dataset's, from its median step);
/// order 0: none.
struct TorqueFilter {
  int order = 0;
  double cutoff = 0.0;  // [Hz]
  double rate = 0.0;    // the dataset's sampling rate [Hz]
  bool active() const { return order > 0 && cutoff > 0.0; }
  /// "order-4 Butterworth at 10 Hz (zero phase), sampled at 1000 Hz".
  std::string describe() const;
};

/// The filter's reach: the half width beyond which the zero-phase impulse response holds at most
/// this share of its absolute sum. A resting sample's unknown static torque s leaks into the
/// filtered torque beyond it by at most this share of |s|: 1 % of a static friction of 2 N m is
/// 0.02 N m, under the filtered noise of a torque sensor.
inline constexpr double kFilterReachShare = 0.01;

/// On a filtered log a joint dwells, and may be sticking (its static torque unknown), where it is
/// slower than kDwellSpeedShare of its RMS speed and its acceleration (central differences of dq)
/// below kDwellAccelerationShare of its RMS acceleration, both over the set. Measured on 20
/// simulated PUMA logs through prepare's defaults (docs/IDENTIFIABILITY.md): with rest alone 80 %
/// of the 95 % intervals held the truth (joint 1 sticks at its stops), with the dwell 94.1 %; on
/// the real Panda log it leaves out no row that changes the fit (held out 0.938 % either way).
inline constexpr double kDwellSpeedShare = 0.02;
inline constexpr double kDwellAccelerationShare = 0.1;

/// On an unfiltered log a row is fitted only where its joint's velocity is beyond kSignMargin
/// times its rest velocity, so that its sign is the motion's and not the noise's. Measured from
/// white velocity noise the rest velocity is 3 sigma (analysis/logs/rest.hpp), which a resting
/// sample's noise passes once in 370: each such row then carries a sign(dq) friction the joint
/// does not have, up to its static band off (25 N m through the PUMA's gears, against 0.5 N m of
/// noise). At 5/3 of it, 5 sigma, once in 1.7 million. (On a filtered log the rows within the
/// filter's reach of a resting sample are left out already, and so are such samples in a rest.) A
/// simulated PUMA with stick-slip friction (60 s, stops, 1e-3 rad/s of velocity noise): 35 of 58 95
/// % intervals held the truth at 3 sigma, Fv up to 24 % off; 55 at 5 sigma, as with noise-free
/// velocities (docs/IDENTIFIABILITY.md).
inline constexpr double kSignMargin = 5.0 / 3.0;

/// The reach of `filter` in samples (filter active; InputError when its cutoff is not below half
/// the rate).
int filterReach(const TorqueFilter& filter);

/// The rows of a fit of `model`'s parameters (its rest velocities and drive terms), per sample of
/// a training set (its index in the set, from 0) and joint.
class FitRows {
 public:
  /// Every row by its own sample: joint j's row is left out where |dq_j| <= kSignMargin rest_j and
  /// the model has a signed_by_velocity term. Stores nothing.
  explicit FitRows(const Model& model);
  /// For a dataset whose torque went through `filter`: `time` and `dq` (joints x samples) of every
  /// sample of the training set; runs split where a step exceeds 1.5 / filter.rate. Each run's
  /// signed_by_velocity columns through the filter, and its rows left out within the reach of a
  /// static sample (at rest, or dwelling). Stores 8 bytes per sample per joint and term, and 1 per
  /// sample per joint (requireMemory). Throws InputError when the sizes disagree or the filter is
  /// not active.
  FitRows(const Model& model, const Eigen::VectorXd& time, const Eigen::MatrixXd& dq,
          const TorqueFilter& filter);

  /// Whether joint j's row of sample s (velocity dq_j) is fitted.
  bool fitted(long long s, int j, double dq_j) const;
  /// Sample s's regressor Y (joints x the model's standard parameters) and torques as the fit
  /// takes them: the rows not fitted zero (Y's and tau's), the filtered columns in place.
  void apply(long long s, const Eigen::Ref<const Eigen::VectorXd>& dq,
             Eigen::Ref<Eigen::MatrixXd> Y, Eigen::Ref<Eigen::VectorXd> tau) const;
  /// What the filtered columns add to `identified`'s drive torque at sample s, joint j (theta its
  /// drive parameters, of the same terms): sum_k theta_k (F[phi_k](s) - phi_k(dq_j)); 0 unfiltered.
  double filteredDriveCorrection(const Model& identified, long long s, int j, double dq_j) const;

  /// Whether any row can be left out (the model has a signed_by_velocity term).
  bool leavesRowsOut() const { return !signed_terms_.empty(); }
  bool filtered() const { return filter_.active(); }
  const TorqueFilter& filter() const { return filter_; }
  /// The filter's reach [samples] (0 unfiltered).
  int reach() const { return reach_; }
  /// The samples in the stored set (0 for the first constructor).
  long long samples() const { return static_cast<long long>(fitted_.cols()); }

 private:
  Model model_;
  std::vector<int> signed_terms_;  // kDriveTermTable rows the model enables, signed_by_velocity
  TorqueFilter filter_;
  int reach_ = 0;
  // Stored for a filtered set: 1 where fitted (joints x samples); the columns through the filter,
  // row j * signed_terms_.size() + t.
  Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> fitted_;
  Eigen::MatrixXd columns_;
};

}  // namespace dynid
