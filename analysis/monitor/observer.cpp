#include "analysis/monitor/observer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/errors.hpp"
#include "core/momentum.hpp"
#include "core/rnea.hpp"

namespace dynid {

// ---- the observer ----

MomentumObserver::MomentumObserver(const Model& model, const Eigen::VectorXd& gain)
    : model_(model), data_(model), gain_(gain) {
  const int n = model.numJoints();
  if (gain.size() != n || !gain.allFinite() || (gain.array() <= 0.0).any())
    throw InputError("the observer gain needs " + std::to_string(n) +
                     " entries, each > 0 and finite [1/s]");
  p0_ = integral_ = r_ = rate_ = Eigen::VectorXd::Zero(n);
}

const Eigen::VectorXd& MomentumObserver::update(double t,
                                                const Eigen::Ref<const Eigen::VectorXd>& q,
                                                const Eigen::Ref<const Eigen::VectorXd>& dq,
                                                const Eigen::Ref<const Eigen::VectorXd>& tau) {
  momentumTerms(model_, data_, q, dq, p_, beta_);
  if (!started_) {
    // r = 0 at the start: the observer assumes no external torque then.
    p0_ = p_;
    integral_.setZero();
    r_.setZero();
    rate_ = tau - beta_;
    t_ = t;
    started_ = true;
    return r_;
  }
  const double dt = t - t_;
  assert(dt > 0.0);
  // Trapezoid: I_k = I_{k-1} + dt/2 (u_{k-1} + r_{k-1} + u_k + r_k), r_k = K (p_k - p0 - I_k),
  // solved for r_k.
  const Eigen::VectorXd u = tau - beta_;
  const Eigen::ArrayXd half = 0.5 * dt * gain_.array();
  const Eigen::VectorXd known = integral_ + 0.5 * dt * (rate_ + u);
  r_ = (gain_.array() * (p_ - p0_ - known).array() / (1.0 + half)).matrix();
  integral_ = known + 0.5 * dt * r_;
  rate_ = u + r_;
  t_ = t;
  return r_;
}

// ---- statistics and thresholds ----

void ResidualStatistics::reset(int n, double block_seconds) {
  sum_squares = rate_sum_squares = max_abs = Eigen::VectorXd::Zero(n);
  block_max = block_sum = block_sum_squares = Eigen::VectorXd::Zero(n);
  rate_time = 0.0;
  block = block_seconds;
  block_time = 0.0;
  blocks = 0;
  samples = 0;
}

void ResidualStatistics::add(const Eigen::VectorXd& r, const Eigen::VectorXd* previous, double dt) {
  sum_squares += r.cwiseAbs2();
  max_abs = max_abs.cwiseMax(r.cwiseAbs());
  // A block is `block` seconds of these samples' own time: a state's samples come in runs, and a
  // block cut short by the end of a run would have a smaller maximum.
  const double step = previous && dt > 0.0 ? dt : 0.0;
  if (block_time + step >= block) {  // the block is complete: its maximum joins the others
    block_sum += block_max;
    block_sum_squares += block_max.cwiseAbs2();
    ++blocks;
    block_max.setZero();
    block_time = 0.0;
  } else {
    block_time += step;
  }
  block_max = block_max.cwiseMax(r.cwiseAbs());
  ++samples;
  if (previous && dt > 0.0) {
    rate_sum_squares += (r - *previous).cwiseAbs2() / dt;  // (dr/dt)^2 dt
    rate_time += dt;
  }
}

Eigen::VectorXd ResidualStatistics::rms() const {
  return samples > 0 ? Eigen::VectorXd((sum_squares / static_cast<double>(samples)).cwiseSqrt())
                     : Eigen::VectorXd::Zero(sum_squares.size());
}

Eigen::VectorXd ResidualStatistics::rateRms() const {
  return rate_time > 0.0 ? Eigen::VectorXd((rate_sum_squares / rate_time).cwiseSqrt())
                         : Eigen::VectorXd::Zero(sum_squares.size());
}

Eigen::VectorXd riceThresholds(const ResidualStatistics& statistics, double rate) {
  const Eigen::VectorXd s = statistics.rms(), ds = statistics.rateRms();
  Eigen::VectorXd out(s.size());
  for (Eigen::Index j = 0; j < s.size(); ++j) {
    double u = 0.0;
    if (s[j] > 0.0 && ds[j] > 0.0) {
      const double ratio = ds[j] / (std::numbers::pi * s[j] * rate);
      u = s[j] * std::sqrt(2.0 * std::log(std::max(ratio, 1.0)));
    }
    double gumbel = 0.0;
    if (statistics.blocks >= 10) {
      const double m = statistics.blocks;
      const double mean = statistics.block_sum[j] / m;
      const double sd = std::sqrt(std::max(0.0, statistics.block_sum_squares[j] / m - mean * mean) *
                                  m / (m - 1.0));
      const double beta = sd * std::sqrt(6.0) / std::numbers::pi;
      const double mu = mean - 0.5772156649015329 * beta;
      const double p = std::min(rate * statistics.block, 0.5);
      gumbel = mu - beta * std::log(-std::log1p(-p));
    }
    out[j] = std::max({u, gumbel, statistics.max_abs[j]});
  }
  return out;
}

// ---- the envelope ----

void ResidualEnvelope::reset(int n) {
  time_.resize(2 * kMaxBuckets);
  low_.resize(n, 2 * kMaxBuckets);
  high_.resize(n, 2 * kMaxBuckets);
  count_ = 0, stride_ = 1, in_bucket_ = 0;
}

void ResidualEnvelope::add(double t, const Eigen::VectorXd& r) {
  if (in_bucket_ == 0) {
    if (count_ == 2 * kMaxBuckets) {
      // Merge neighbouring buckets: the stride doubles, the envelope stays the same.
      for (int b = 0; b < kMaxBuckets; ++b) {
        time_[b] = time_[2 * b];
        low_.col(b) = low_.col(2 * b).cwiseMin(low_.col(2 * b + 1));
        high_.col(b) = high_.col(2 * b).cwiseMax(high_.col(2 * b + 1));
      }
      count_ = kMaxBuckets;
      stride_ *= 2;
    }
    time_[count_] = t;
    low_.col(count_) = r;
    high_.col(count_) = r;
    ++count_;
  } else {
    low_.col(count_ - 1) = low_.col(count_ - 1).cwiseMin(r);
    high_.col(count_ - 1) = high_.col(count_ - 1).cwiseMax(r);
  }
  in_bucket_ = (in_bucket_ + 1) % stride_;
}

}  // namespace dynid
