// Least squares on a floating robot's sensor set (docs/FLOATING.md): the base parameters from the
// rows sensor_sets.hpp gives, with each sample's noise carried through to its rows.
//
// Each sample measures the joint torques tau (noise sd sigma_tau per joint) and, per active
// contact, its force lambda in base-frame axes (sd sigma_force per force component, sigma_moment
// per moment component of a frame contact). Its rows' noise covariance follows from the rows:
//   wrenches          y = J_b^T lambda              C = J_b^T S_l J_b
//   torques_wrenches  y = (0, tau) + J^T lambda     C = diag(0, S_t) + J^T S_l J
//   torques_contacts  y = N^T (0, tau)              C = N^T diag(0, S_t) N
// (S_t, S_l the diagonal variances). Ordinary least squares ignores C and reports the white
// covariance s^2 (W^T W)^-1; generalized least squares whitens each sample's rows by C^-1/2 and
// reports s^2 (W^T C^-1 W)^-1 with s^2 the whitened residuals' variance (1 when the noise levels
// are right), which is what makes its intervals calibrated when channels differ. Rows no channel
// reaches (the base rows in flight, which hold exactly in this noise model) are weighted as
// near-constraints: their variance 1e-6 of the sample's largest.
#pragma once

#include <vector>

#include "identifiability/floating/sensor_sets.hpp"

namespace dynid {

/// One sample: its floating regressor, what holds (FloatingStateSampler::jacobian) and what was
/// measured.
struct FloatingMeasurement {
  Eigen::MatrixXd Y;       // (6 + n) x p
  Eigen::MatrixXd J;       // k x (6 + n), k >= 0
  Eigen::VectorXd tau;     // n
  Eigen::VectorXd forces;  // k: the active contacts' forces, J's rows' order
  /// The force components' noise variances (k, J's rows' order: sigma_force^2 or sigma_moment^2).
  Eigen::VectorXd force_variance;
  /// 1 for a force row that is a moment (a frame contact's first three), J's rows' order; empty:
  /// none is. Read by fitFloatingFeasible, which estimates forces' and moments' noise apart.
  std::vector<char> moment_rows;
};

struct FloatingFitOptions {
  bool generalized = true;  // generalized least squares (else ordinary)
  /// Each joint torque's noise variance (n entries; empty: all 1, the rows then weighted alike).
  Eigen::VectorXd torque_variance;
};

struct FloatingFit {
  Eigen::VectorXd beta;         // base parameters (base's order)
  Eigen::MatrixXd covariance;   // of beta
  Eigen::VectorXd sd;           // sqrt of its diagonal
  double residual_scale = 0.0;  // s: the (whitened) residuals' standard deviation
  int rows = 0;
};

/// The fit of `base` (a set's structural base parameters) on the samples' rows for `set`. Throws
/// InputError when the rows cannot determine every base parameter (fewer rows than parameters, or
/// a rank-deficient base regressor) or sizes disagree.
FloatingFit fitFloating(const BaseParameters& base, SensorSet set,
                        const std::vector<FloatingMeasurement>& samples,
                        const FloatingFitOptions& options = {});

/// The noise variances of a robot's channels: every joint torque's [N^2 m^2], every contact force
/// component's [N^2] and every contact moment component's [N^2 m^2].
struct ChannelVariances {
  double torque = 1.0, force = 1.0, moment = 1.0;
};

/// Generalized least squares with the channels' variances estimated from the data (feasible
/// GLS): each sample's row covariance is C = s_t^2 G_t + s_f^2 G_f + s_m^2 G_m (the table above,
/// per channel), and the variances are the fixed point of
///   s_g^2 <- s_g^2 * sum_k r_k^T C_k^-1 G_g,k C_k^-1 r_k / ((R - p) / R * sum_k tr(C_k^-1 G_g,k))
/// (r_k a sample's residual, R rows, p parameters: restricted maximum likelihood's update with
/// the leverage taken as its mean), iterated until they change by less than 1e-5 relative (at most
/// 100 times), each kept above 1e-6 of its first estimate (a channel the rows barely see runs to
/// zero otherwise, and C with it). A channel the set does not read keeps its variance (torques
/// for wrenches, forces and moments for torques_contacts). The same sensors feed every set: the
/// richest (torques_wrenches) estimates them best. Returns the fit at the estimated variances,
/// which `estimated` receives. Throws as fitFloating.
FloatingFit fitFloatingFeasible(const BaseParameters& base, SensorSet set,
                                const std::vector<FloatingMeasurement>& samples,
                                ChannelVariances* estimated = nullptr);

/// Least squares of rows the caller forms from each sample (W[k] x = y[k], W[k] of the set's row
/// count: a few columns of its rows, and what the rest of the model leaves of its measurements),
/// weighted by the set's row covariance at `variances` (ordinary least squares when null), with
/// unit-norm columns in the solve. Throws InputError as fitFloating.
FloatingFit fitFloatingRows(SensorSet set, const std::vector<FloatingMeasurement>& samples,
                            const std::vector<Eigen::MatrixXd>& W,
                            const std::vector<Eigen::VectorXd>& y,
                            const ChannelVariances* variances);

/// The set's rows in standard coordinates (sensorRows: every column of the floating vector),
/// stacked over the samples, whitened by their row covariance at `variances` (unweighted when
/// null) and compressed to the (p + 1)-square upper triangle R of the QR of [W | y], so that
/// |W theta - y|^2 = |R(0:p, 0:p) theta - R(0:p, p)|^2 + R(p, p)^2 for every theta. Throws
/// InputError for no sample or samples of different sizes.
Eigen::MatrixXd floatingStandardFactor(SensorSet set,
                                       const std::vector<FloatingMeasurement>& samples,
                                       const ChannelVariances* variances);

}  // namespace dynid
