// What a least-squares estimate of the base parameters is: the method, the estimate with its
// statistics, and a torque prediction's errors. The dense solve (least_squares.hpp) and the stream
// (least_squares_stream.hpp) both return these.
#pragma once

#include <Eigen/Core>

namespace dynid {

enum class LeastSquaresMethod {
  kOrdinary,  // OLS: every row weighted equally
  kWeighted,  // WLS (Gautier): joint j's rows weighted by 1 / sigma_j, sigma_j from OLS residuals
};

const char* leastSquaresMethodName(LeastSquaresMethod method);

struct BaseEstimate {
  LeastSquaresMethod method = LeastSquaresMethod::kOrdinary;
  Eigen::VectorXd beta;        // base parameter estimates (BaseParameters order), SI units
  Eigen::MatrixXd covariance;  // of beta
  Eigen::VectorXd std_dev;     // sqrt(diag(covariance))
  Eigen::VectorXd relative_std_dev_percent;  // 100 std_dev / |beta| (infinity when beta = 0)
  double condition_number = 0.0;             // of the column-scaled (and weighted) base regressor
  /// Of the base regressor as it is (weighted for WLS), in physical units: what most papers report
  /// (it depends on the units of the parameters; the column-scaled one does not).
  double condition_number_unscaled = 0.0;
  /// How well the data excite each base parameter on its own: sqrt(1 - R^2) of its (weighted)
  /// column regressed on the other base columns, i.e. 1 / sqrt(variance inflation factor), in
  /// (0, 1]. 1: no other parameter's torque signature mimics it; near 0: nearly a combination of
  /// the others, so its estimate is as uncertain as that combination.
  Eigen::VectorXd independence;
  Eigen::VectorXd joint_sigma;   // per-joint torque noise estimated from the OLS residuals [N m]
  Eigen::VectorXd residual_rms;  // per-joint RMS of tau - W1 beta [N m]
  Eigen::VectorXd measured_rms;  // per-joint RMS of the measured tau [N m]
  /// |tau - W1 beta| / |tau| over every joint and sample (the literature's relative error), and
  /// per joint (residual_rms / measured_rms; infinity for a joint whose torque is 0).
  double relative_error = 0.0;
  Eigen::VectorXd joint_relative_error;
  int num_samples = 0;
  /// Per joint, the rows the fit took (identifiability/rows/fit_rows.hpp: fewer than num_samples
  /// where a joint at rest had its row left out); empty: num_samples each. The per-joint
  /// statistics above are over these rows.
  Eigen::VectorXd fitted_rows;
};

/// A torque prediction against measured torques.
struct Validation {
  Eigen::VectorXd torque_rms;      // per joint RMS of tau - W1 beta [N m]
  Eigen::VectorXd normalised_rms;  // torque_rms / RMS(tau) per joint (infinity for a zero tau)
  double relative_error = 0.0;     // |tau - W1 beta| / |tau| over every joint and sample
  int num_samples = 0;
};
/// Sets estimate.relative_error and joint_relative_error from its residual_rms and measured_rms.
void setRelativeErrors(BaseEstimate& estimate);

}  // namespace dynid
