// The runs wing's room for the arm itself: the robot a command works on (a robot spec, or an
// identify estimate.json with its parameters), its kinematics signature and consistency, and its
// dynamics at one state (dynid model, dynid dynamics). Nothing here prints or writes a report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "analysis/estimation/streaming.hpp"
#include "analysis/records/model_source.hpp"
#include "core/model.hpp"
#include "core/parameters.hpp"
#include "core/spatial.hpp"

namespace dynid {

// ---- models and dynamics ----

/// Each link frame in the base frame at q = 0, to compare with a datasheet's drawing.
std::vector<Pose<double>> linkFramesAtZero(const Model& model);
/// The kinematics an estimate's parameters refer to: per link its frame at q = 0 (rotation
/// row-major, then origin) and its joint axis in the base frame at q = 0, 15 numbers per link.
/// Estimates record it, and `predict` refuses a robot whose kinematics differ.
Eigen::MatrixXd kinematicsSignature(const Model& model);
/// What differs between recorded kinematics (an estimate's rows) and `model`'s: the joint count,
/// else the first link whose frame origin, frame rotation or joint axis differs beyond 1e-9, with
/// how much; "" when they are the same. `whose` names the recorded robot in the message.
std::string kinematicsDifference(const nlohmann::json& recorded, const Model& model,
                                 const std::string& whose = "the estimate's robot");
/// The same against a recorded robot (a search's embedded one).
std::string kinematicsDifference(const Model& recorded, const Model& model,
                                 const std::string& whose);

/// Every physical-consistency violation of the model's links (empty: all consistent).
std::vector<ConsistencyViolation> consistencyViolations(const Model& model);

/// The dynamics at one state: tau = RNEA(q, dq, ddq), or ddq = ABA(q, dq, tau) when `tau` is
/// given; M = CRBA(q) either way.
struct DynamicsOutcome {
  Eigen::VectorXd q, dq, ddq, tau;
  Eigen::MatrixXd M;
};
/// q, dq and the given one of ddq, tau have n entries (InputError otherwise). Throws
/// NumericalError when the dynamics are singular at the state (a massless moving subtree).
DynamicsOutcome dynamicsAt(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                           const std::optional<Eigen::VectorXd>& ddq,
                           const std::optional<Eigen::VectorXd>& tau);

// ---- simulation ----

/// The robot an identify estimate.json names (or `robot_spec`), with the estimate's drive terms,
/// standard parameters and rest velocities (none in a version 1 estimate); `spec_used` and `method`
/// (when given) receive the robot spec used and the estimate's method. Throws ParseError for a
/// malformed estimate, InputError when it does not fit the robot (another robot, another drive
/// model: the parameter named). `band`, when given, receives the estimate's prediction band (its
/// base covariance and joint noise; nothing for an estimate written before dynid recorded them).
/// `source`, when given, receives where the robot came from: the estimate's model_source for the
/// model it embeds, else the file loaded (`robot_spec`, or an older estimate's robot_spec).
Model estimateModel(const std::string& file, const std::string& robot_spec,
                    std::string* spec_used = nullptr, std::string* method = nullptr,
                    std::optional<PredictionBand>* band = nullptr, ModelSource* source = nullptr);

/// The arm given as an identify estimate.json (its robot loaded, or `robot_spec` when given, with
/// the estimate's parameters) or as a robot spec (loadRobot with `drive_terms`). Throws as
/// loadRobot and estimateModel; InputError for --robot or drive terms given where they do not
/// apply.
struct LoadedArm {
  Model model;
  std::string robot_spec;      // the robot's spec (the estimate's, or `arm` itself)
  ModelSource source;          // where the robot came from (documents embed it with the model)
  bool from_estimate = false;  // the parameters came from an estimate.json
  /// The estimate's torque source: the torque constants and gear ratios its motor currents were
  /// converted with (empty: its torques were not currents, or the arm is no estimate).
  std::vector<double> torque_constants, gear_ratios;
};
LoadedArm loadArm(const std::string& arm, const std::string& robot_spec,
                  const std::optional<DriveTerms>& drive_terms, std::vector<std::string>* warnings);

/// The velocities and stamps of a dataset file's first kRestSamples samples (memory bounded
/// whatever the file's length): what the rest velocities are measured on. Only `time` and `dq` are
/// filled; q, ddq and tau have no samples.
inline constexpr int kRestSamples = 200000;
Trajectory restSamplesOf(const std::string& file, int joints);

// ---- the GC-error searches ----

/// `threads`, or every core for 0.
int resolveThreads(int threads);

}  // namespace dynid
