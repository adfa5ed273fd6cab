// The monitor's residual and its statistics: the generalized-momentum observer, a clean run's
// residual statistics, the thresholds they give at a false-alarm rate, and the residual's envelope
// for figures. Constant memory.
#pragma once

#include <Eigen/Core>

#include "core/data.hpp"
#include "core/model.hpp"

namespace dynid {

/// The observer's default gain [1/s]: a 10 ms time constant, so a step of external torque shows
/// 99 % of its size within 50 ms.
inline constexpr double kDefaultObserverGain = 100.0;

/// The generalized-momentum observer r = K (p - p0 - integral (tau - beta + r) dt), p = M dq,
/// beta = g + tau_f - C^T dq (core/momentum.hpp): r follows the external joint torque through a
/// first-order lag of time constant 1/K per joint. Discretised by the trapezoid rule, solved for
/// r at each sample (stable for any step), so irregular sampling is fine.
class MomentumObserver {
 public:
  /// gain: n entries, each > 0 and finite [1/s] (InputError otherwise). Keeps a reference to model.
  MomentumObserver(const Model& model, const Eigen::VectorXd& gain);
  /// Forgets the past: the next sample starts again with r = 0.
  void restart() { started_ = false; }
  /// Feeds the sample at time t (q, dq, tau: n entries) and returns r [N m]. The first sample
  /// after construction or restart() sets p0 and returns 0; t must increase (asserted).
  const Eigen::VectorXd& update(double t, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const Eigen::Ref<const Eigen::VectorXd>& dq,
                                const Eigen::Ref<const Eigen::VectorXd>& tau);
  const Eigen::VectorXd& residual() const { return r_; }

 private:
  const Model& model_;
  Data data_;
  Eigen::VectorXd gain_, p_, beta_, p0_, integral_, r_, rate_;  // rate_: tau - beta + r
  double t_ = 0.0;
  bool started_ = false;
};

/// A residual's statistics over a clean run, per joint, in constant memory: moments, and the
/// maxima of |r| over blocks of `block` seconds of the samples' own time (the steps between
/// consecutive samples: runs of samples, a state's, join into whole blocks), for the tail.
struct ResidualStatistics {
  Eigen::VectorXd sum_squares, rate_sum_squares, max_abs;   // r^2, (dr/dt)^2 dt-weighted, |r|
  Eigen::VectorXd block_max, block_sum, block_sum_squares;  // this block's max; over blocks
  double rate_time = 0.0;                                   // the time the rate sums cover [s]
  double block = 1.0, block_time = 0.0;                     // [s]: its length, this one's so far
  int blocks = 0;                                           // completed blocks
  long long samples = 0;
  void reset(int n, double block_seconds = 1.0);
  /// One sample; `previous` and its step dt > 0 when it follows another without a gap.
  void add(const Eigen::VectorXd& r, const Eigen::VectorXd* previous, double dt);
  Eigen::VectorXd rms() const;
  Eigen::VectorXd rateRms() const;  // RMS of dr/dt [N m/s]
};

/// Per-joint thresholds [N m] for `rate` false alarms per second on one joint, the largest of
///   - Rice's formula for the upcrossings of |r| by a stationary Gaussian process of RMS s and
///     rate RMS s': 2 s' / (2 pi s) exp(-u^2 / (2 s^2)) = rate, u = s sqrt(2 ln(s' / (pi s rate)));
///   - the Gumbel law of the block maxima (fitted by moments: beta = sd sqrt(6) / pi,
///     mu = mean - 0.5772 beta), at the probability rate * block of one block exceeding u:
///     u = mu - beta ln(-ln(1 - rate * block)); it follows heavy tails (friction at velocity
///     reversals, model errors) that the Gaussian formula underrates; with 10 blocks or more;
///   - the largest |r| seen in the calibration (a clean run raises no alarm).
Eigen::VectorXd riceThresholds(const ResidualStatistics& statistics, double rate);

/// A residual's envelope for figures: per joint the min and max over buckets of stride samples,
/// the stride doubling to keep at most 2 kMaxEnvelope buckets. Constant memory.
class ResidualEnvelope {
 public:
  static constexpr int kMaxBuckets = 2048;
  void reset(int n);
  void add(double t, const Eigen::VectorXd& r);
  int count() const { return count_; }
  Eigen::VectorXd time() const { return time_.head(count_); }  // each bucket's first sample
  Eigen::MatrixXd low() const { return low_.leftCols(count_); }
  Eigen::MatrixXd high() const { return high_.leftCols(count_); }

 private:
  Eigen::VectorXd time_;
  Eigen::MatrixXd low_, high_;
  int count_ = 0, stride_ = 1, in_bucket_ = 0;
};

}  // namespace dynid
