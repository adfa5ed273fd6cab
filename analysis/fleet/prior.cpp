#include "analysis/fleet/prior.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/special_functions/erf.hpp>

#include "core/errors.hpp"

namespace dynid {

namespace {

// A variance below this counts as this (a parameter a robot's data fix exactly would otherwise
// weigh infinitely): far below any estimate's variance in SI units.
constexpr double kVarianceFloor = 1e-300;

/// sum_i w_i (x_i - mean_w)^2 with w_i = 1 / (v_i + t).
double weightedSquares(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t) {
  const Eigen::ArrayXd w = 1.0 / (v.array().max(kVarianceFloor) + t);
  const double mean = (w * x.array()).sum() / w.sum();
  return (w * (x.array() - mean).square()).sum();
}

void checkMembers(const std::vector<FleetMember>& members, const FleetOptions& options) {
  if (!(options.flag_level > 0.0 && options.flag_level <= 0.5))
    throw InputError("`flag_level` must be in (0, 0.5]");
  if (options.max_rounds < 1) throw InputError("`max_rounds` must be >= 1");
  if (members.size() < 3)
    throw InputError("a fleet needs three robots or more to learn its spread (" +
                     std::to_string(members.size()) + " given)");
  const Eigen::Index p = members.front().estimate.size();
  for (const FleetMember& m : members) {
    if (m.estimate.size() != p || m.covariance.rows() != p || m.covariance.cols() != p)
      throw InputError(m.name + ": " + std::to_string(m.estimate.size()) +
                       " base parameters, the fleet's first robot has " + std::to_string(p));
    if (!m.estimate.allFinite() || !m.covariance.allFinite() ||
        (m.covariance.diagonal().array() < 0.0).any())
      throw InputError(m.name + ": an estimate or variance that is not finite or negative");
  }
}

struct Round {
  Eigen::VectorXd mean, spread2, precision;  // precision: sum of the weights, per parameter
  Eigen::VectorXd spread2_upper;             // the spread's upper confidence bound (Q-profile)
};

/// The prior learnt from the members marked in `in`.
Round learn(const std::vector<FleetMember>& members, const std::vector<bool>& in) {
  const Eigen::Index p = members.front().estimate.size();
  std::vector<int> idx;
  for (std::size_t r = 0; r < members.size(); ++r)
    if (in[r]) idx.push_back(static_cast<int>(r));
  const auto m = static_cast<Eigen::Index>(idx.size());
  Round out{Eigen::VectorXd(p), Eigen::VectorXd(p), Eigen::VectorXd(p), Eigen::VectorXd(p)};
  Eigen::VectorXd x(m), v(m);
  for (Eigen::Index k = 0; k < p; ++k) {
    for (Eigen::Index i = 0; i < m; ++i) {
      x[i] = members[static_cast<std::size_t>(idx[static_cast<std::size_t>(i)])].estimate[k];
      v[i] = members[static_cast<std::size_t>(idx[static_cast<std::size_t>(i)])].covariance(k, k);
    }
    const double t = pauleMandelSpread(x, v);
    const Eigen::ArrayXd w = 1.0 / (v.array().max(kVarianceFloor) + t);
    out.spread2[k] = t;
    out.precision[k] = w.sum();
    out.mean[k] = (w * x.array()).sum() / w.sum();
    out.spread2_upper[k] = spreadUpperBound(x, v);
  }
  return out;
}

/// A robot's z and two-sided p per parameter.
struct Scores {
  Eigen::VectorXd z, p;
};

/// Robot r's z against the prior learnt without it (`in` less r): the fleet it is compared with
/// is the others', so that an odd robot neither widens the spread it is judged by nor moves the
/// mean (what a new robot's estimate is predicted to lie within). The spread it is judged by is
/// the upper end of its confidence interval (Q-profile), not its point estimate: a spread learnt
/// from a few robots may be larger than they show. p: the Gaussian's two-sided, of that z.
Scores scores(const std::vector<FleetMember>& members, std::vector<bool> in, std::size_t r,
              const Round& with_r) {
  const FleetMember& member = members[r];
  const bool learnt_from = in[r];
  Round without;
  if (learnt_from) {
    in[r] = false;
    without = learn(members, in);
  }
  const Round& p = learnt_from ? without : with_r;
  const Eigen::Index n = p.mean.size();
  Scores out{Eigen::VectorXd(n), Eigen::VectorXd(n)};
  for (Eigen::Index k = 0; k < n; ++k) {
    const double v = std::max(member.covariance(k, k), kVarianceFloor);
    out.z[k] =
        (member.estimate[k] - p.mean[k]) / std::sqrt(v + p.spread2_upper[k] + 1.0 / p.precision[k]);
    out.p[k] = std::erfc(std::abs(out.z[k]) / std::sqrt(2.0));
  }
  return out;
}

/// The posterior of a robot inside the fleet.
void shrink(const FleetMember& member, const Round& prior, FleetVerdict& verdict) {
  const Eigen::MatrixXd t = prior.spread2.asDiagonal();
  Eigen::MatrixXd s = member.covariance + t;
  s = 0.5 * (s + s.transpose()).eval();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s);
  Eigen::MatrixXd gain;  // (S + T)^-1 T
  if (ldlt.info() == Eigen::Success && ldlt.isPositive())
    gain = ldlt.solve(t);
  else
    gain = s.completeOrthogonalDecomposition().solve(t);
  verdict.posterior = prior.mean + gain.transpose() * (member.estimate - prior.mean);
  const Eigen::MatrixXd cov = t - t * gain;
  verdict.posterior_std = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace

double pauleMandelSpread(const Eigen::VectorXd& values, const Eigen::VectorXd& variances) {
  return spreadWhere(values, variances, static_cast<double>(values.size() - 1));
}

double spreadUpperBound(const Eigen::VectorXd& values, const Eigen::VectorXd& variances) {
  const boost::math::chi_squared chi2(static_cast<double>(values.size() - 1));
  return spreadWhere(values, variances, boost::math::quantile(chi2, kSpreadBoundTail));
}

double spreadWhere(const Eigen::VectorXd& values, const Eigen::VectorXd& variances, double target) {
  if (weightedSquares(values, variances, 0.0) <= target) return 0.0;
  // Q(t) decreases in t: bracket the root by doubling from the values' own variance, then bisect.
  const double mean = values.mean();
  double hi =
      std::max((values.array() - mean).square().sum() / std::max(target, 1e-3), kVarianceFloor);
  while (weightedSquares(values, variances, hi) > target && hi < 1e300) hi *= 2.0;
  double lo = 0.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (weightedSquares(values, variances, mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

FleetPrior fleetPrior(const std::vector<FleetMember>& members, const FleetOptions& options) {
  checkMembers(members, options);
  const std::size_t n = members.size();
  const Eigen::Index p = members.front().estimate.size();
  FleetPrior out;
  // Two-sided: P(|Z| > z*) = flag_level / (robots x parameters).
  out.z_threshold =
      std::sqrt(2.0) * boost::math::erfc_inv(options.flag_level / static_cast<double>(n * p));
  out.test_level = options.flag_level / static_cast<double>(n * p);
  const std::size_t fewest = std::max<std::size_t>(3, (n + 1) / 2);
  std::vector<bool> in(n, true);
  Round prior;
  std::vector<Scores> z(n);
  for (out.rounds = 1;; ++out.rounds) {
    prior = learn(members, in);
    std::vector<bool> next(n);
    for (std::size_t r = 0; r < n; ++r) {
      z[r] = scores(members, in, r, prior);
      next[r] = z[r].p.minCoeff() >= out.test_level;
    }
    if (next == in) break;
    if (static_cast<std::size_t>(std::count(next.begin(), next.end(), true)) < fewest) {
      out.converged = false;
      break;
    }
    if (out.rounds >= options.max_rounds) {
      out.converged = false;
      break;
    }
    in = next;
  }
  out.mean = prior.mean;
  out.spread = prior.spread2.cwiseSqrt();
  out.spread_upper = prior.spread2_upper.cwiseSqrt();
  out.mean_std = prior.precision.cwiseInverse().cwiseSqrt();
  out.learnt_from = static_cast<int>(std::count(in.begin(), in.end(), true));
  out.robots.resize(n);
  for (std::size_t r = 0; r < n; ++r) {
    FleetVerdict& v = out.robots[r];
    v.z = z[r].z;
    v.p_value = z[r].p;
    v.learnt_from = in[r];
    std::vector<int> order(static_cast<std::size_t>(p));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return v.p_value[a] != v.p_value[b] ? v.p_value[a] < v.p_value[b]
                                          : std::abs(v.z[a]) > std::abs(v.z[b]);
    });
    v.farthest = order.front();
    for (int k : order)
      if (v.p_value[k] < out.test_level) v.outside_parameters.push_back(k);
    v.outside = !v.outside_parameters.empty();
    if (v.outside) {
      v.posterior = members[r].estimate;
      v.posterior_std = members[r].covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
    } else {
      shrink(members[r], prior, v);
    }
  }
  return out;
}

}  // namespace dynid
