#include "analysis/runs/arm.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <thread>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/records/upgrade.hpp"
#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/kinematics.hpp"
#include "core/parameters.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"

namespace dynid {

int resolveThreads(int threads) {
  return threads > 0 ? threads
                     : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// ---- models and dynamics ----

std::vector<Pose<double>> linkFramesAtZero(const Model& model) {
  Data data(model);
  return forwardKinematics(model, data, Eigen::VectorXd::Zero(model.numJoints()));
}

std::vector<ConsistencyViolation> consistencyViolations(const Model& model) {
  std::vector<ConsistencyViolation> all;
  for (int i = 0; i < model.numJoints(); ++i) {
    auto v = checkPhysicalConsistency(model.inertias()[i], i, model.link_names[i]);
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

DynamicsOutcome dynamicsAt(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& dq,
                           const std::optional<Eigen::VectorXd>& ddq,
                           const std::optional<Eigen::VectorXd>& tau) {
  const int n = model.numJoints();
  Data data(model);
  DynamicsOutcome out{q, dq, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), {}};
  // With tau: ddq = ABA(q, dq, tau), and tau is echoed; otherwise tau = RNEA(q, dq, ddq).
  if (tau) {
    out.tau = *tau;
    out.ddq = aba(model, data, q, dq, *tau);
  } else {
    if (ddq) out.ddq = *ddq;
    out.tau = rnea(model, data, q, dq, out.ddq);
  }
  out.M = crba(model, data, q);
  if (!out.ddq.allFinite() || !out.tau.allFinite() || !out.M.allFinite())
    throw NumericalError("the dynamics of '" + model.name +
                         "' are singular at this state: the mass matrix is not positive definite "
                         "(is a moving subtree massless?)");
  return out;
}

Eigen::MatrixXd kinematicsSignature(const Model& model) {
  const std::vector<Pose<double>> frames = linkFramesAtZero(model);
  Eigen::MatrixXd out(model.numJoints(), 15);
  for (int i = 0; i < model.numJoints(); ++i) {
    const Eigen::Matrix3d& r = frames[i].rotation;
    // The axis is given in the joint frame; the link frame is the joint frame times the body
    // placement, so the axis in the base frame is R_link R_body^T axis.
    const Eigen::Vector3d axis =
        r * model.body_placements()[i].rotation.transpose() * model.axes()[i];
    out.row(i) << r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2),
        frames[i].translation.transpose(), axis.transpose();
  }
  return out;
}

namespace {

/// The robot an estimate embeds (estimate.json 5), with the drive terms it names. Throws ParseError
/// naming the file's `model` field.
Model embeddedModel(const EstimateRecord& estimate, const std::string& file) {
  Model model = modelFromJson(estimate.model.dump(), file + " (its model)");
  if (driveTermsKeys(model.driveTerms()) != estimate.drive_terms)
    throw ParseError(file, 0, "model.drive_terms", "differ from the estimate's drive_terms");
  return model;
}

}  // namespace

std::string kinematicsDifference(const nlohmann::json& recorded, const Model& model,
                                 const std::string& whose) {
  const Eigen::MatrixXd mine = kinematicsSignature(model);
  if (!recorded.is_array() || recorded.size() != static_cast<std::size_t>(mine.rows()))
    return "it has " + std::to_string(mine.rows()) + " joints, " + whose + " " +
           std::to_string(recorded.is_array() ? recorded.size() : 0);
  constexpr double kSame = 1e-9;  // round-off of the frames' products, far below any real change
  for (Eigen::Index i = 0; i < mine.rows(); ++i) {
    double rotation = 0.0, origin = 0.0, axis = 0.0;
    for (Eigen::Index c = 0; c < 15; ++c) {
      const nlohmann::json& v = recorded[static_cast<std::size_t>(i)][static_cast<std::size_t>(c)];
      const double d = v.is_number() ? std::abs(v.get<double>() - mine(i, c)) : 1e300;
      double& worst = c < 9 ? rotation : c < 12 ? origin : axis;
      worst = std::max(worst, d);
    }
    const std::string link = "link " + std::to_string(i + 1) + " (" + model.link_names[i] + ")";
    if (origin > kSame)
      return link + "'s frame at q = 0 lies " + formatNumber(origin, 3) +
             " m (largest coordinate) from " + whose + "'s";
    if (rotation > kSame)
      return link + "'s frame at q = 0 is turned from " + whose + "'s (rotation entries " +
             "differ by up to " + formatNumber(rotation, 3) + ")";
    if (axis > kSame)
      return "joint " + std::to_string(i + 1) + " (" + model.joint_names[i] +
             ") turns about another axis (components differ by up to " + formatNumber(axis, 3) +
             ")";
  }
  return "";
}

std::string kinematicsDifference(const Model& recorded, const Model& model,
                                 const std::string& whose) {
  const Eigen::MatrixXd rows = kinematicsSignature(recorded);
  nlohmann::json json = nlohmann::json::array();
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < rows.cols(); ++c) row.push_back(rows(i, c));
    json.push_back(row);
  }
  return kinematicsDifference(json, model, whose);
}

Model estimateModel(const std::string& file, const std::string& robot_spec, std::string* spec_used,
                    std::string* method, std::optional<PredictionBand>* band, ModelSource* source) {
  const EstimateRecord estimate = estimateRecordFrom(parseJson(readFile(file), file), file);
  const std::string spec = robot_spec.empty() ? estimate.robot_spec : robot_spec;
  if (spec.empty())
    throw ParseError(file, 0, "robot_spec",
                     "the estimate does not say which robot it is for: give `robot`");
  if (spec_used != nullptr) *spec_used = spec;
  if (method != nullptr) *method = estimate.method;
  std::string terms;
  for (const std::string& t : estimate.drive_terms) terms += (terms.empty() ? "" : ",") + t;
  RobotOptions options;
  try {
    options.drive_terms = parseDriveTerms(terms.empty() ? "none" : terms);
  } catch (const InputError& e) {
    throw ParseError(file, 0, "drive_terms", e.what());
  }
  Model model;
  ModelSource from{spec, estimate.model_file, estimate.model_sha256};
  if (robot_spec.empty() && !estimate.model.is_null()) {
    model = embeddedModel(estimate, file);  // the robot the estimate embeds: no file needed
  } else if (robot_spec.empty()) {
    try {  // the robot an older estimate names: a failure names the estimate and its field
      model = loadRobot(specBesideDocument(spec, file), options);
      from = modelSourceOf(specBesideDocument(spec, file));
      from.spec = spec;
    } catch (const Error& e) {
      throw ParseError(file, 0, "robot_spec", std::string("cannot load its robot: ") + e.what());
    }
  } else {
    model = loadRobot(spec, options);
    from = modelSourceOf(spec);
  }
  if (source != nullptr) *source = from;
  model.setStandardParameters(
      standardVectorFrom(estimate, standardParameterNames(model.parameterLayout()), file, spec));
  if (!estimate.rest_velocities.empty()) {
    if (static_cast<int>(estimate.rest_velocities.size()) != model.numJoints())
      throw ParseError(file, 0, "rest_velocity.velocity",
                       "has " + std::to_string(estimate.rest_velocities.size()) +
                           " entries, the robot " + std::to_string(model.numJoints()) + " joints");
    model.rest_velocities = estimate.rest_velocities;
  }
  // Same parameter names on other kinematics (a standard-DH robot and its URDF, whose link frames
  // differ) would give wrong torques silently: compare the recorded kinematics.
  if (!estimate.kinematics.is_null()) {
    const std::string difference = kinematicsDifference(estimate.kinematics, model);
    if (!difference.empty())
      throw InputError(file + ": robot '" + spec +
                       "' is not the robot the estimate was made for: " + difference);
  }
  if (band && !estimate.band_columns.empty()) {
    const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
    PredictionBand b;
    for (std::size_t c = 0; c < estimate.band_columns.size(); ++c) {
      const auto it = std::find(names.begin(), names.end(), estimate.band_columns[c]);
      if (it == names.end())
        throw ParseError(file, 0, JsonReader::index("base_covariance.columns", c),
                         "'" + estimate.band_columns[c] + "' is not a parameter of the robot");
      b.independent.push_back(static_cast<int>(it - names.begin()));
    }
    b.covariance = estimate.covariance;
    if (estimate.joint_sigma.size() != model.numJoints())
      throw ParseError(file, 0, "joint_sigma",
                       "expected " + std::to_string(model.numJoints()) +
                           " numbers with the "
                           "base covariance");
    b.noise_sigma = estimate.joint_sigma;
    *band = std::move(b);
  }
  return model;
}

LoadedArm loadArm(const std::string& arm, const std::string& robot_spec,
                  const std::optional<DriveTerms>& drive_terms,
                  std::vector<std::string>* warnings) {
  LoadedArm out;
  std::error_code error;
  if (std::filesystem::path(arm).extension() == ".json" &&
      std::filesystem::is_regular_file(arm, error)) {
    const nlohmann::json document = parseJson(readFile(arm), arm);
    // estimate.json 1 wrote no kind: its keys tell it (it was read as a robot model before).
    const bool untitled_estimate = document.is_object() && !document.contains("kind") &&
                                   document.contains("standard_estimate") &&
                                   document.contains("base_parameters");
    if (isDocumentOfKind(document, kEstimateDocument) || untitled_estimate) {
      if (drive_terms)
        throw InputError(arm + ": an estimate carries its own drive terms; drop `drive_terms`");
      out.model = estimateModel(arm, robot_spec, &out.robot_spec, nullptr, nullptr, &out.source);
      out.from_estimate = true;
      const EstimateRecord record = estimateRecordFrom(document, arm);
      if (warnings != nullptr && record.schema_version < kEstimateDocument.schema_version)
        warnings->push_back(olderVersionNote(arm, kEstimateDocument.kind, record.schema_version,
                                             kEstimateDocument.schema_version));
      out.torque_constants = record.torque_constants;
      out.gear_ratios = record.gear_ratios;
      return out;
    }
  }
  if (!robot_spec.empty())
    throw InputError("`robot` applies to an estimate.json arm; '" + arm + "' is a robot itself");
  RobotOptions options;
  options.drive_terms = drive_terms;
  out.model = loadRobot(arm, options, warnings);
  out.robot_spec = arm;
  out.source = modelSourceOf(arm);
  return out;
}

Trajectory restSamplesOf(const std::string& file, int joints) {
  DatasetReader reader(file, joints);
  // Only the stamps and velocities are kept: q, ddq and tau stay empty (0 samples), so that the
  // 200,000 samples cost 8 doubles each, not 29.
  Eigen::VectorXd time(kRestSamples);
  Eigen::MatrixXd dq(joints, kRestSamples);
  Trajectory chunk;
  int count = 0;
  while (count < kRestSamples) {
    const int got = reader.read(chunk, std::min(kStreamChunkSamples, kRestSamples - count));
    if (got == 0) break;
    time.segment(count, got) = chunk.time;
    dq.middleCols(count, got) = chunk.dq;
    count += got;
  }
  Trajectory out;
  out.time = time.head(count);
  out.dq = dq.leftCols(count);
  out.q.resize(joints, 0);
  out.ddq.resize(joints, 0);
  out.tau.resize(joints, 0);
  return out;
}

}  // namespace dynid
