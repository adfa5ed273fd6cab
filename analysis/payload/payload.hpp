// dynid payload: what was added at a link of an identified arm (a tool, a gripper and its load),
// with the arm held fixed. From one prepared log with the payload attached, or from a loaded and an
// unloaded run of the same motion (the torque difference, which cancels what the arm model gets
// wrong), it gives the payload's 10 standard parameters in the attachment frame, its mass, centre
// of mass and inertia about the centre of mass with principal axes, physically consistent, with
// 95 % intervals, which of them the motion determines, and the smallest payload it resolves. With
// a known mass, the loaded/unloaded pair gives the drives' torque-constant scale factors instead.
// docs/PAYLOAD.md gives the method, the checks and the vendors' conventions.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/records/model_source.hpp"
#include "core/model.hpp"
#include "core/spatial.hpp"
#include "core/trajectory.hpp"
#include "identifiability/payload.hpp"

namespace dynid {

struct PayloadRequest {
  Model arm;               // the identified arm, drive terms included
  std::string arm_source;  // how the arm was given (an estimate file, a URDF, a robot spec)
  ModelSource arm_model;   // where the arm's robot came from (payload.json embeds it with `arm`)
  std::string data_file;   // a dataset CSV with the payload attached (dynid prepare's train.csv)
  std::string unloaded_file = "";  // the same commanded motion without it (empty: none)
  /// The same in memory instead of the files (Python's Dataset): not owned; the file names are
  /// then only what the documents call them.
  const Trajectory* data = nullptr;
  const Trajectory* unloaded = nullptr;
  std::string link = "";                          // the link it is attached to (empty: the last)
  Pose<double> tool = Pose<double>::Identity();   // the attachment frame in the link's frame
  std::optional<Vector10d> prior = std::nullopt;  // in the attachment frame; none: uninformative
  double prior_weight = 1.0;                      // > 0
  bool refit_friction = false;  // the arm's friction terms re-estimated with the payload
  std::optional<double> known_mass = std::nullopt;  // [kg] > 0: drive gains (needs unloaded_file)
  std::optional<Eigen::Vector3d> known_com = std::nullopt;  // [m] in the attachment frame
  /// [rad] the largest RMS difference of a joint's position between the loaded and the unloaded
  /// run (after the best time shift) for them to count as the same motion.
  double max_motion_difference = 0.05;
  /// A URDF of the arm to write back with the payload as a fixed link (empty: none), and whether
  /// the arm's own parameters are written into it first (an arm from an estimate.json).
  std::string urdf_file = "";
  bool urdf_carries_arm = false;

  /// Throws InputError naming the field out of its range.
  void check() const;
};

/// One reported quantity, with its 95 % interval value +- half_width.
struct PayloadQuantity {
  std::string name;   // "m", "cx", "Ixx_c", "I1", "mx", ...
  std::string unit;   // "kg", "m", "kg m^2", "kg m"
  std::string group;  // "mass", "centre of mass", "inertia about the centre of mass",
                      // "principal moments", "standard parameters", "principal axes" (the
                      // angle from the attachment axis, and the axis's 95 % angle)
  double value = 0.0;
  double std_dev = 0.0;     // inf when the data do not see it
  double half_width = 0.0;  // 1.96 std_dev
  bool determined = false;  // docs/PAYLOAD.md, "Determined"
};

struct FrictionChange {
  std::string name;  // "Fv3"
  double arm = 0.0;  // the arm model's value
  double with_payload = 0.0;
  double std_dev = 0.0;
};

struct DriveGains {
  Eigen::VectorXd scale, scale_std;      // true torque / measured torque per joint
  std::vector<char> determined;          // 95 % half-width <= 0.5 % of the scale
  std::vector<double> torque_constants;  // prepare.json's constants x scale (empty: not recorded)
  int iterations = 0;
};

struct PayloadOutcome {
  std::string mode;  // "single" (one log, the arm model subtracted) or "difference"
  std::string arm_source, data_file, unloaded_file, robot, link_name;
  Model arm;              // the request's arm, as payload.json embeds it
  ModelSource arm_model;  // and where its robot came from
  int link = 0;           // 0-based
  Pose<double> tool;
  int samples = 0;
  double shift = 0.0;                      // [s] unloaded time = loaded time + shift
  Eigen::VectorXd motion_difference;       // per joint RMS [rad] after the shift
  Vector10d standard = Vector10d::Zero();  // consistent, in the attachment frame
  Vector10d least_squares = Vector10d::Zero();
  Vector10d prior = Vector10d::Zero();
  bool prior_given = false;
  double prior_weight = 1.0;
  Matrix10d covariance = Matrix10d::Zero();  // of the least-squares standard parameters
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_com = Eigen::Matrix3d::Zero();  // about the COM, attachment axes
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();
  Eigen::Matrix3d principal_axes = Eigen::Matrix3d::Identity();  // columns, det +1
  /// Sets `standard` and the body fields derived from it (mass, com, inertia_com, principal
  /// moments and axes). Throws InputError for a mass <= 0.
  void setBody(const Vector10d& body);
  std::vector<PayloadQuantity> quantities;
  std::vector<std::string> unseen;    // combinations the motion does not excite at all
  std::vector<std::string> combined;  // combinations determined where their parts are not
  double smallest_mass = 0.0;         // [kg] resolved to +-20 % (95 %)
  double smallest_moment = 0.0;       // [kg m^2] a principal moment resolved to +-20 % (95 %)
  std::vector<std::string> advice;
  bool least_squares_consistent = false, converged = false;
  std::string termination;
  Eigen::VectorXd noise, residual_rms, target_rms;  // per joint [N m]
  int batch = 1;
  std::vector<FrictionChange> friction;
  std::optional<DriveGains> gains;
  std::vector<std::string> warnings;
  std::optional<std::string> urdf;  // the URDF carrying the payload, when asked for
  /// Figures: the payload's measured torque (target) and the estimate's, at most 2000 samples.
  Eigen::VectorXd plot_time;
  Eigen::MatrixXd plot_measured, plot_predicted;
};

/// Runs it. Throws InputError for a request out of range, a link the arm does not have, a log of
/// another joint count, a pair whose motions differ, a log the arm model does not explain (another
/// robot); ParseError for a malformed dataset.
PayloadOutcome payloadRun(const PayloadRequest& request);

}  // namespace dynid
