// The fleet's prior, learnt from the robots of one model (empirical Bayes, docs/FLEET.md "A
// fleet"). Each robot r's base parameters are a draw around the fleet's mean,
//   beta_r ~ N(mu, diag(tau^2)),
// and its own estimate b_r ~ N(beta_r, S_r) (S_r its covariance). Per base parameter k:
//   tau_k^2 by Paule-Mandel: the weighted sum of squares about the weighted mean equals its
//     expectation, sum_r w_rk (b_rk - mu_k)^2 = m - 1 with w_rk = 1 / (S_r,kk + tau_k^2) over the
//     m robots the prior is learnt from (tau_k = 0 when the robots agree within their own sigma);
//   mu_k the weighted mean with those weights.
// A robot lies outside the fleet when one of its parameters does: z_rk = (b_rk - mu_k^(-r)) /
// sqrt(S_r,kk + tau_k^(-r)^2 + var mu_k^(-r)) (the prior learnt without robot r: an odd robot
// neither widens the spread it is judged by nor moves the mean), when its two-sided p is below
// flag_level / (robots x parameters) (Bonferroni: a fleet of robots alike has one flagged with
// probability flag_level at most), i.e. |z| > z*. The spread in z is the upper end of the spread's
// 95 % confidence interval (Q-profile, Viechtbauer 2007: sum_r (b_rk - mu_k)^2 / (S_r,kk + t) =
// the chi-square (m - 1) quantile at 2.5 %) rather than its point estimate: learnt from a few
// robots, the spread may be larger than they show (four robots that are one real arm differ by
// |z| 5.2 against their point spread, docs/FLEET.md). The
// prior is learnt again without the robots outside, until the set holds (at most `max_rounds`
// rounds; never fewer than half the robots, nor than three, learn it), so that an outlier neither
// widens tau nor moves mu. A robot inside the fleet gets the posterior mu + T (S_r + T)^-1 (b_r -
// mu), covariance T - T (S_r + T)^-1 T (T = diag(tau^2)): its own estimate where its data are sure,
// the fleet's where they are not. A robot outside keeps its own estimate (the prior does not
// describe it).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// One robot's estimate of the base parameters and its covariance.
struct FleetMember {
  std::string name;
  Eigen::VectorXd estimate;
  Eigen::MatrixXd covariance;
};

struct FleetOptions {
  /// The probability that a fleet of robots all alike has one flagged, in (0, 0.5].
  double flag_level = 0.01;
  int max_rounds = 10;  // >= 1
};

/// What the fleet says of one robot.
struct FleetVerdict {
  Eigen::VectorXd z;                    // per base parameter, against the fleet without it
  Eigen::VectorXd p_value;              // two-sided, of z (Gaussian)
  bool outside = false;                 // some p_k < the test level
  std::vector<int> outside_parameters;  // those k, by p increasing
  int farthest = 0;                     // the parameter of the smallest p
  bool learnt_from = false;             // among the robots the prior was learnt from
  Eigen::VectorXd posterior;            // inside: shrunk toward the fleet; outside: its own
  Eigen::VectorXd posterior_std;
};

struct FleetPrior {
  Eigen::VectorXd mean;          // mu, per base parameter
  Eigen::VectorXd spread;        // tau: the robots' spread about mu beyond their own sigma
  Eigen::VectorXd spread_upper;  // the upper end of its 95 % confidence interval
  Eigen::VectorXd mean_std;      // the standard deviation of mu
  double test_level = 0.0;       // flag_level / (robots x parameters): a p below it flags
  double z_threshold = 0.0;      // z*: the Gaussian bound at that level
  int learnt_from = 0;           // robots the prior was learnt from
  int rounds = 0;                // rounds until the set held
  /// False when the robots outside would leave fewer than half the fleet (or three) to learn
  /// from: the fleet is then not one population, and the last set's prior is kept.
  bool converged = true;
  std::vector<FleetVerdict> robots;  // in the members' order
};

/// The prior of `members` (three or more, of one parameter count; every covariance square, of
/// that size, symmetric with a finite non-negative diagonal) and each robot's verdict. Throws
/// InputError naming the member or the option at fault.
FleetPrior fleetPrior(const std::vector<FleetMember>& members, const FleetOptions& options = {});

/// tau^2 of one parameter by Paule-Mandel from `values` and their variances (same size >= 2).
double pauleMandelSpread(const Eigen::VectorXd& values, const Eigen::VectorXd& variances);
/// The upper end of tau^2's 95 % confidence interval (Q-profile).
double spreadUpperBound(const Eigen::VectorXd& values, const Eigen::VectorXd& variances);
/// The t >= 0 at which sum_i (x_i - mean_t)^2 / (v_i + t) = target (mean_t weighted by
/// 1 / (v_i + t)); 0 when the sum at 0 is already at or below it.
double spreadWhere(const Eigen::VectorXd& values, const Eigen::VectorXd& variances, double target);
/// The chi-square quantile of the spread's upper bound: 2.5 % (a two-sided 95 % interval).
inline constexpr double kSpreadBoundTail = 0.025;

}  // namespace dynid
