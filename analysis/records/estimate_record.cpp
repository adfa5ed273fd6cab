#include "analysis/records/estimate_record.hpp"

#include <algorithm>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "analysis/records/provenance.hpp"
#include "core/errors.hpp"
#include "core/integrators.hpp"
#include "core/parameters.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"
#include "data/model_json.hpp"

namespace dynid {

using nlohmann::json;

namespace {

/// A standard vector from {name: value} (every name of the layout required, each a finite number
/// within +-kMaxParameterMagnitude).
Eigen::VectorXd standardFrom(const json& values, const std::vector<std::string>& names,
                             const std::string& file, const std::string& where) {
  const JsonReader read(file);
  read.object(values, where);
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string path = where + "." + names[k];
    if (!values.contains(names[k]))
      read.fail(path, "missing (does `robot`/`drives` match the run?)");
    theta[static_cast<Eigen::Index>(k)] =
        read.number(values[names[k]], path, -kMaxParameterMagnitude, kMaxParameterMagnitude);
  }
  return theta;
}

/// A search.json's header and top-level keys; its version. Versions 1 (before the robot was
/// embedded) and 2 (before the provenance) read the same: model, model_source and provenance are
/// for the record (refine checks its robot against the model).
int checkSearchDocument(const JsonReader& read, const json& start) {
  const int version = documentVersion(start, kSearchDocument.schema_version);
  read.header(start, version, nullptr);
  read.onlyKeys(start, "",
                {"schema_version",
                 "kind",
                 "method",
                 "robot",
                 "settings",
                 "termination",
                 "initial_gc_error",
                 "final_gc_error",
                 "estimate",
                 "initial_estimate",
                 "history",
                 "evaluations",
                 "seconds",
                 "initial_parameter_error",
                 "final_parameter_error",
                 "evaluated",
                 "validation",
                 "model",
                 "model_source",
                 "provenance"});
  if (start.contains("model")) read.object(start["model"], "model");
  if (start.contains("model_source"))
    modelSourceFrom(start["model_source"], read.file(), "model_source");
  if (start.contains("provenance")) provenanceFrom(start, read.file());
  return version;
}

}  // namespace

RefineStart refineStartFrom(const json& start, const std::string& from, const Model& robot,
                            const SpaceOptions& space, const SegmentOptions& segments) {
  const std::vector<std::string> names = standardParameterNames(robot.parameterLayout());
  RefineStart out{"", space, segments, robot, robot, std::nullopt};
  try {
    if (start.contains("settings") && start.contains("estimate")) {
      out.kind = "search";
      const JsonReader read(from);
      out.version = checkSearchDocument(read, start);
      const json& s = read.field(start, "", "settings");
      read.onlyKeys(s, "settings",
                    {"form",
                     "free_parameters",
                     "range",
                     "absolute_range",
                     "mass_constraint",
                     "total_mass",
                     "horizon",
                     "segments",
                     "random_segments",
                     "integrator",
                     "step",
                     "normalise",
                     "seed",
                     "budget_evaluations",
                     "budget_seconds",
                     "gc_tolerance",
                     "population",
                     "elites",
                     "migration",
                     "mutation_rate",
                     "mutation_scale",
                     "evaluations_per_seed",
                     "data"});
      const auto named = [&](const char* key, auto parse) {
        const std::string text = read.string(s, "settings", key);
        try {
          return parse(text);
        } catch (const std::exception& e) {
          read.fail(std::string("settings.") + key, e.what());
        }
      };
      out.space = SpaceOptions{};
      out.space.form = named("form", [](const std::string& t) { return parseParameterForm(t); });
      out.space.relative_range = read.number(s, "settings", "range", 0.0, 1e3);
      out.space.absolute_range = read.number(s, "settings", "absolute_range", 0.0, 1e6);
      out.space.total_mass_constraint = read.boolean(s, "settings", "mass_constraint");
      out.space.total_mass = read.number(s, "settings", "total_mass", 1e-12, 1e6);
      out.segments = SegmentOptions{};
      out.segments.horizon = read.number(s, "settings", "horizon", 1e-9, 1e4);
      out.segments.num_segments =
          static_cast<int>(read.integer(s, "settings", "segments", 0, 1000000));
      out.segments.random_starts = read.boolean(s, "settings", "random_segments");
      out.segments.seed = read.unsignedInteger(s, "settings", "seed");
      out.segments.integrator =
          named("integrator", [](const std::string& t) { return parseIntegrator(t); });
      out.segments.step = read.number(s, "settings", "step", 1e-6, 10.0);
      out.segments.normalise = read.boolean(s, "settings", "normalise");
      out.initial.setStandardParameters(standardFrom(start.at("initial_estimate").at("standard"),
                                                     names, from, "initial_estimate.standard"));
      out.estimate.setStandardParameters(
          standardFrom(start.at("estimate").at("standard"), names, from, "estimate.standard"));
      // Free exactly what the search freed.
      const std::vector<std::string> free =
          read.strings(read.field(s, "settings", "free_parameters"), "settings.free_parameters");
      const std::vector<std::string> all =
          out.space.form == ParameterForm::kPaper
              ? paperParameterNames(robot.numJoints())
              : standardParameterNames({robot.numJoints(), DriveTerms::none()});
      for (const std::string& name : all)
        if (std::find(free.begin(), free.end(), name) == free.end())
          out.space.fixed.push_back(name);
      for (const std::string& name : free)
        if (std::find(all.begin(), all.end(), name) == all.end())
          read.fail("settings.free_parameters", "'" + name + "' is not a parameter of the robot");
    } else if (start.contains("standard_estimate")) {
      out.kind = "estimate";
      const EstimateRecord record = estimateRecordFrom(start, from);
      out.version = record.schema_version;
      out.initial.setStandardParameters(standardVectorFrom(record, names, from, ""));
      out.estimate = out.initial;
    } else {
      throw ParseError(from, 0, "", "neither a dynid search.json nor an identify estimate.json");
    }
    if (start.contains("model")) out.made_on = modelFromJson(start["model"].dump(), from);
  } catch (const json::exception& e) {
    throw ParseError(from, 0, "", std::string("missing or malformed field: ") + e.what());
  }
  return out;
}

namespace {

/// torque_source: {kind "current", torque_constants, gear_ratios}, finite and non-zero.
void readTorqueSource(const JsonReader& read, const json& value, EstimateRecord& out) {
  const json& source = read.object(value, "torque_source");
  read.onlyKeys(source, "torque_source", {"kind", "torque_constants", "gear_ratios"});
  if (read.string(source, "torque_source", "kind") != "current")
    read.fail("torque_source.kind", "expected 'current'");
  for (const auto& [key, target] : {std::pair{"torque_constants", &out.torque_constants},
                                    std::pair{"gear_ratios", &out.gear_ratios}}) {
    const std::string path = std::string("torque_source.") + key;
    const Eigen::VectorXd v = read.vector(read.field(source, "torque_source", key), path);
    if (!v.allFinite() || (v.array() == 0.0).any())
      read.fail(path, "expected finite, non-zero numbers");
    target->assign(v.data(), v.data() + v.size());
  }
  if (out.torque_constants.empty()) read.fail("torque_source.torque_constants", "empty");
}

}  // namespace

namespace {

/// estimate.json's base_covariance (each base parameter's regressor column and the covariance) and
/// joint_sigma, predict's torque bands.
void readBaseCovariance(const JsonReader& read, const json& document, EstimateRecord& out) {
  const json& c = read.object(document["base_covariance"], "base_covariance");
  read.onlyKeys(c, "base_covariance", {"note", "columns", "matrix", "policy"});
  if (c.contains("policy")) {
    const json& policy = read.object(c["policy"], "base_covariance.policy");
    read.onlyKeys(policy, "base_covariance.policy",
                  {"name", "batch", "inflation", "autocorrelation", "note"});
    out.covariance_policy = read.string(policy, "base_covariance.policy", "name");
    if (out.covariance_policy != "hac" && out.covariance_policy != "white")
      read.fail("base_covariance.policy.name", "expected \"hac\" or \"white\"");
  }
  out.band_columns =
      read.strings(read.field(c, "base_covariance", "columns"), "base_covariance.columns");
  const long b = static_cast<long>(out.band_columns.size());
  const json& rows =
      read.array(read.field(c, "base_covariance", "matrix"), "base_covariance.matrix");
  if (static_cast<long>(rows.size()) != b)
    read.fail("base_covariance.matrix", "expected " + std::to_string(b) + " rows");
  // Every row's length first: the matrix is allocated only for numbers the file holds.
  for (long i = 0; i < b; ++i) {
    const nlohmann::json& row = rows[static_cast<std::size_t>(i)];
    if (!row.is_array() || static_cast<long>(row.size()) != b)
      read.fail(JsonReader::index("base_covariance.matrix", static_cast<std::size_t>(i)),
                "expected " + std::to_string(b) + " numbers");
  }
  out.covariance.resize(b, b);
  for (long i = 0; i < b; ++i)
    out.covariance.row(i) =
        read.vector(rows[static_cast<std::size_t>(i)],
                    JsonReader::index("base_covariance.matrix", static_cast<std::size_t>(i)), b)
            .transpose();
  if (!out.covariance.allFinite() ||
      (out.covariance - out.covariance.transpose()).norm() > 1e-9 * out.covariance.norm() ||
      (out.covariance.diagonal().array() < 0.0).any())
    read.fail("base_covariance.matrix", "expected a finite symmetric covariance");
  if (document.contains("joint_sigma")) {
    out.joint_sigma = read.vector(document["joint_sigma"], "joint_sigma");
    if (!out.joint_sigma.allFinite() || (out.joint_sigma.array() < 0.0).any())
      read.fail("joint_sigma", "expected finite numbers >= 0");
  }
}

/// model (an object, parsed as a model by its reader) and model_source: {spec, file, sha256}, the
/// last two null for a built-in robot.
void readModelSource(const JsonReader& read, const json& document, const std::string& file,
                     EstimateRecord& out) {
  out.model = read.object(document["model"], "model");
  const ModelSource source =
      modelSourceFrom(read.field(document, "", "model_source"), file, "model_source");
  out.model_file = source.file;
  out.model_sha256 = source.sha256;
}

}  // namespace

EstimateRecord estimateRecordFrom(const json& document, const std::string& file) {
  const JsonReader read(file);
  // Every earlier version is read: 1 (no rest velocities), 2 (no covariance policy), 3 (no
  // fit_rows), 4 (no model embedded: the robot is loaded from robot_spec).
  const int version = documentVersion(document, kEstimateDocument.schema_version);
  read.header(document, version, nullptr);
  if (document.contains("kind") && read.string(document, "", "kind") != kEstimateDocument.kind)
    read.fail("kind", std::string("expected '") + kEstimateDocument.kind + "'");
  read.onlyKeys(document, "",
                {"schema_version",
                 "kind",
                 "robot",
                 "robot_spec",
                 "kinematics",
                 "drives",
                 "drive_terms",
                 "method",
                 "data",
                 "num_base",
                 "base_parameters",
                 "condition_number",
                 "condition_number_unscaled",
                 "joint_sigma",
                 "residual_rms",
                 "measured_rms",
                 "relative_error",
                 "joint_relative_error",
                 "standard_estimate",
                 "physically_consistent",
                 "write_back",
                 "validation",
                 "reversals",
                 "base_covariance",
                 "combined",
                 "front",
                 "torque_source",
                 "rest_velocity",
                 "fit_rows",
                 "model",
                 "model_source",
                 "provenance"});
  if (document.contains("provenance")) provenanceFrom(document, file);
  EstimateRecord out;
  out.schema_version = version;
  if (document.contains("rest_velocity")) {
    const json& rest = read.object(document["rest_velocity"], "rest_velocity");
    const json& velocity =
        read.array(read.field(rest, "rest_velocity", "velocity"), "rest_velocity.velocity");
    for (std::size_t j = 0; j < velocity.size(); ++j)
      out.rest_velocities.push_back(read.number(velocity[j],
                                                JsonReader::index("rest_velocity.velocity", j), 0.0,
                                                kMaxParameterMagnitude));
  }
  if (document.contains("torque_source")) readTorqueSource(read, document["torque_source"], out);
  if (document.contains("model")) readModelSource(read, document, file, out);
  if (document.contains("base_covariance")) readBaseCovariance(read, document, out);
  if (document.contains("robot_spec")) out.robot_spec = read.string(document, "", "robot_spec");
  if (document.contains("method")) out.method = read.string(document, "", "method");
  if (document.contains("drive_terms"))
    out.drive_terms = read.strings(document["drive_terms"], "drive_terms");
  const json& standard = read.field(document, "", "standard_estimate");
  read.onlyKeys(standard, "standard_estimate", {"note", "values"});
  const json& values =
      read.object(read.field(standard, "standard_estimate", "values"), "standard_estimate.values");
  for (const auto& [name, value] : values.items())
    out.standard[name] = read.number(value, "standard_estimate.values." + name,
                                     -kMaxParameterMagnitude, kMaxParameterMagnitude);
  if (document.contains("kinematics")) {
    const json& rows = read.array(document["kinematics"], "kinematics");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string path = JsonReader::index("kinematics", i);
      if (!rows[i].is_array() || rows[i].size() != 15) read.fail(path, "expected 15 numbers");
      for (std::size_t c = 0; c < 15; ++c)
        if (!rows[i][c].is_number() && !rows[i][c].is_null())
          read.fail(JsonReader::index(path, c), "expected a number");
    }
    out.kinematics = rows;
  }
  return out;
}

BaseParametersRecord baseParametersFrom(const nlohmann::json& document, const std::string& file) {
  const JsonReader read(file);
  const json& base = read.array(read.field(document, "", "base_parameters"), "base_parameters");
  BaseParametersRecord out;
  out.estimate.resize(static_cast<Eigen::Index>(base.size()));
  out.std_dev.resize(static_cast<Eigen::Index>(base.size()));
  for (std::size_t j = 0; j < base.size(); ++j) {
    const std::string path = JsonReader::index("base_parameters", j);
    out.names.push_back(read.string(base[j], path, "name"));
    out.expressions.push_back(read.string(base[j], path, "expression"));
    const auto e = static_cast<Eigen::Index>(j);
    out.estimate[e] =
        read.number(base[j], path, "estimate", -kMaxParameterMagnitude, kMaxParameterMagnitude);
    out.std_dev[e] = read.number(base[j], path, "std_dev", 0.0, kMaxParameterMagnitude);
  }
  return out;
}

Eigen::VectorXd standardVectorFrom(const EstimateRecord& record,
                                   const std::vector<std::string>& names, const std::string& file,
                                   const std::string& robot_spec) {
  const std::string robot = robot_spec.empty() ? "the robot" : "robot '" + robot_spec + "'";
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto it = record.standard.find(names[k]);
    if (it == record.standard.end())
      throw ParseError(file, 0, "standard_estimate.values." + names[k],
                       "missing: " + robot + " has this parameter (" +
                           std::to_string(names.size()) + " in all, the estimate " +
                           std::to_string(record.standard.size()) +
                           "): the estimate was made for another robot or drive terms, or edited");
    theta[static_cast<Eigen::Index>(k)] = it->second;
  }
  for (const auto& [name, value] : record.standard)
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw ParseError(file, 0, "standard_estimate.values." + name,
                       "is not a parameter of " + robot +
                           ": the estimate was made for another robot or drive terms");
  return theta;
}

}  // namespace dynid
