// estimate.json (dynid identify, rendered by reports/identification_report) read back for
// predict and refine, and the start a refinement reads from a search.json or an estimate.json.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/model.hpp"
#include "search/gc_problem.hpp"
#include "search/parameter_space.hpp"

namespace dynid {

/// What a refinement starts from, read from a search.json or an estimate.json.
struct RefineStart {
  std::string kind;  // "search" or "estimate"
  SpaceOptions space;
  SegmentOptions segments;
  Model initial, estimate;  // the space's initial model and the start
  /// The robot the document embeds (a search.json from version 2, an estimate.json from 5): the
  /// refinement's robot must have its kinematics.
  std::optional<Model> made_on;
  int version = 0;  // the document's schema_version (an earlier one is read as it is)
};
/// Reads `document` (the contents of `file`). For a search.json, the space and segments are the
/// search's and exactly its free parameters are freed; for an estimate.json, `space` and
/// `segments` are used as given. Every standard parameter of `robot`'s layout must be present.
/// Throws ParseError naming the file and field.
RefineStart refineStartFrom(const nlohmann::json& document, const std::string& file,
                            const Model& robot, const SpaceOptions& space,
                            const SegmentOptions& segments);

/// What predict and refine read from an `identify` estimate.json.
struct EstimateRecord {
  int schema_version = 0;                  // the version it was written in (read as it is)
  std::string robot_spec;                  // "" when the estimate does not say
  std::string method;                      // "" when absent
  std::vector<std::string> drive_terms;    // keys: "fv", "fc", ...
  std::map<std::string, double> standard;  // standard_estimate.values
  nlohmann::json kinematics;               // the recorded kinematics signature, or null
  /// base_covariance (absent from older estimates): each base parameter's regressor column (a
  /// standard parameter's name) and the covariance; joint_sigma, the residual noise per joint.
  std::vector<std::string> band_columns;
  Eigen::MatrixXd covariance;
  /// base_covariance.policy.name (absent before version 3: "white", the only policy then).
  std::string covariance_policy = "white";
  Eigen::VectorXd joint_sigma;
  /// torque_source (absent when the torques were not converted from motor currents): the torque
  /// constants and gear ratios (empty: 1) dynid prepare --current used.
  std::vector<double> torque_constants, gear_ratios;
  /// rest_velocity.velocity (absent from version 1): each joint's rest velocity, as measured on
  /// the training data; empty when absent.
  std::vector<double> rest_velocities;
  /// model (version 5 on): the robot the estimate was made for, as a dynid JSON model (null
  /// before); model_source's file name and SHA-256 (empty for a built-in robot or before).
  nlohmann::json model;
  std::string model_file, model_sha256;
};
/// Reads an estimate.json document strictly: schema_version kEstimateDocument's or any earlier one
/// (its kind, when given, kEstimateDocument's), unknown top-level keys refused, robot_spec a
/// string, drive_terms an array of names, standard_estimate {note, values} with every value a
/// finite number within
/// +-kMaxParameterMagnitude, kinematics an array of 15-entry rows. Throws ParseError naming `file`
/// and the field.
EstimateRecord estimateRecordFrom(const nlohmann::json& document, const std::string& file);
/// estimate.json's base parameters: each one's name, expression, estimate and standard deviation.
struct BaseParametersRecord {
  std::vector<std::string> names, expressions;
  Eigen::VectorXd estimate, std_dev;
};
/// Reads `document`'s base_parameters (required; each estimate within +-kMaxParameterMagnitude,
/// each standard deviation in [0, kMaxParameterMagnitude]). Throws ParseError naming `file` and the
/// field.
BaseParametersRecord baseParametersFrom(const nlohmann::json& document, const std::string& file);

/// The standard vector in the order of `names` (a robot's layout). Throws ParseError naming the
/// first missing or extra parameter ("standard_estimate.values.Ixx3") and saying the estimate was
/// made for another robot (or edited) when the names differ.
Eigen::VectorXd standardVectorFrom(const EstimateRecord& record,
                                   const std::vector<std::string>& names, const std::string& file,
                                   const std::string& robot_spec);

}  // namespace dynid
