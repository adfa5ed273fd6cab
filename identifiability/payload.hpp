// One rigid body added to a link of a known robot (a payload, a tool): its 10 standard parameters
// from the torques it adds, with the rest of the robot held fixed. The body's torques are linear in
// its parameters (the link's 10 regressor columns, moved into the body's frame), so the problem is
// a small least-squares problem: weighted per joint, physically consistent through the entropic
// estimator of physically_consistent.hpp on one body, with a covariance that allows for
// correlated residuals (filtered logs). docs/PAYLOAD.md gives the method and its checks.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/spatial.hpp"

namespace dynid {

using Vector10d = Eigen::Matrix<double, 10, 1>;
using Matrix10d = Eigen::Matrix<double, 10, 10>;

/// The linear map from a body's standard parameters in frame T to the same body's in frame L,
/// where `pose` places T in L: phi_L = A phi_T (the spatial inertia's change of frame, linear in
/// the parameters).
Matrix10d standardTransform(const Pose<double>& pose);

/// The rows of a payload problem, sample by sample: the n x 10 regressor of the body (in its own
/// frame), n x extra further columns estimated with it (e.g. changes of friction) and the n
/// torques the body is to explain. Rows k n + j are joint j of sample k.
class PayloadRows {
 public:
  PayloadRows(int num_joints, int extra_columns);
  /// Appends one sample. Throws InputError on wrong sizes or a value that is not finite.
  void add(const Eigen::Ref<const Eigen::MatrixXd>& body,
           const Eigen::Ref<const Eigen::MatrixXd>& extra,
           const Eigen::Ref<const Eigen::VectorXd>& target);
  /// Reserves room for `samples` samples (checks the memory limit first).
  void reserve(int samples);

  int numJoints() const { return n_; }
  int numExtra() const { return extra_; }
  int numSamples() const { return samples_; }
  /// [extra | body] (rows x (extra + 10)) and the targets, in sample order.
  Eigen::MatrixXd design() const { return design_.topRows(rows()); }
  Eigen::VectorXd target() const { return target_.head(rows()); }
  Eigen::Index rows() const { return static_cast<Eigen::Index>(samples_) * n_; }

 private:
  int n_ = 0, extra_ = 0, samples_ = 0;
  Eigen::MatrixXd design_;
  Eigen::VectorXd target_;
};

struct PayloadFitOptions {
  /// The prior body of the entropic divergence (standard parameters in the body's frame): moved
  /// just inside the physical set when it is on or outside it. None: an uninformative prior, a
  /// homogeneous sphere of density `prior_density` with the least-squares mass (at least 1 g)
  /// centred at the least-squares centre of mass (within 1 m of the frame's origin): its moments
  /// scale with the payload (0.4 m r^2, r = (3 m / (4 pi rho))^1/3: 3.7e-7 kg m^2 for 10 g, 7.9e-4
  /// for 1 kg), so that a light tool's moments are not drawn up toward a large sphere's.
  std::optional<Vector10d> prior;
  double prior_weight = 1.0;      // > 0, chi-square units (PhysicalOptions::prior_weight)
  double prior_density = 2700.0;  // [kg/m^3] the uninformative prior's (aluminium)
  /// [m] the length that puts a mass, a first moment and an inertia on one scale for the rank
  /// analysis (m, h / L, I / L^2).
  double length = 0.1;
  /// Samples per batch of the covariance's batch means; 0: from the residuals' autocorrelation
  /// (identifiability/uncertainty/score_covariance.hpp, the one covariance policy).
  int batch = 0;
};

struct PayloadFit {
  Vector10d least_squares = Vector10d::Zero();  // weighted least squares
  Vector10d theta = Vector10d::Zero();          // physically consistent
  Eigen::VectorXd extra, extra_least_squares;   // the extra columns' values (at theta / at LS)
  /// Covariance of [extra; body] (least squares; batch means of the per-sample scores, so
  /// correlated residuals widen it). Infinite variance along directions the data do not see.
  Eigen::MatrixXd covariance;
  Eigen::VectorXd noise;         // per joint: residual standard deviation of the first fit [N m]
  Eigen::VectorXd residual_rms;  // per joint at theta [N m]
  Eigen::VectorXd target_rms;    // per joint [N m]
  int batch = 1;                 // samples per batch of the covariance
  /// Singular values of the whitened body block (extra eliminated) in scaled units (m, h / L,
  /// I / L^2), largest first, and the scaled directions whose value is below 1e-8 of the
  /// largest: combinations of the body's parameters the torques cannot see at all.
  Eigen::VectorXd singular_values;
  Eigen::MatrixXd null_directions;      // 10 x k, standard units, unit norm in scaled units
  Vector10d prior = Vector10d::Zero();  // the prior used
  bool least_squares_consistent = false;
  bool converged = false;
  std::string termination;
};

/// The fit. Throws InputError when there are fewer rows than unknowns or a joint's targets are
/// all zero and no noise can be estimated; NumericalError when the solve fails.
PayloadFit fitPayload(const PayloadRows& rows, const PayloadFitOptions& options);

/// Drive gains from a body of known mass: measured_j = g_j x (true torque_j), the body's torques
/// being the targets (a loaded minus an unloaded run). Fits g (one per joint) and the body's
/// parameters other than the mass (and the centre of mass when known) by Gauss-Newton from the
/// linear form s_j target = body torque (s = 1 / g). `arm_difference` (rows() entries, or empty):
/// the arm model's torque at the loaded sample minus at the unloaded one, true units, which the
/// targets had subtracted: the measured difference of the runs is then g x (arm_difference +
/// body torque), so that motions that differ (the load changes the tracking) scale right too.
struct GainFit {
  Eigen::VectorXd scale;      // s_j = 1 / g_j: true torque over measured torque
  Eigen::VectorXd scale_std;  // its standard deviation (inf when not seen)
  Vector10d theta = Vector10d::Zero();
  Eigen::MatrixXd covariance;  // of [g; free body parameters]
  Eigen::VectorXd noise, residual_rms, target_rms;
  int batch = 1, iterations = 0;
};
GainFit fitDriveGains(const PayloadRows& rows, double mass,
                      const std::optional<Eigen::Vector3d>& com, int batch = 0,
                      const Eigen::VectorXd& arm_difference = Eigen::VectorXd());

}  // namespace dynid
