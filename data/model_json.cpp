#include "data/model_json.hpp"

#include <cmath>
#include <limits>
#include <map>

#include <Eigen/LU>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/json_number.hpp"

namespace dynid {

using nlohmann::json;

namespace {

json poseToJson(const Pose<double>& pose) {
  json rotation = json::array();
  for (int r = 0; r < 3; ++r)
    rotation.push_back({pose.rotation(r, 0), pose.rotation(r, 1), pose.rotation(r, 2)});
  return {{"rotation", rotation},
          {"translation", {pose.translation.x(), pose.translation.y(), pose.translation.z()}}};
}

/// Reads fields of a JSON document, naming the path of whatever is wrong.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw ParseError(file_, 0, path, message);
  }
  const json& field(const json& object, const std::string& path, const char* key) const {
    if (!object.is_object()) fail(path, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(join(path, key), "missing");
    return *it;
  }
  double number(const json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number");
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "not finite");
    return x;
  }
  double number(const json& object, const std::string& path, const char* key) const {
    return number(field(object, path, key), join(path, key));
  }
  double limit(const json& object, const std::string& path, const char* key,
               double unlimited) const {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return unlimited;
    return number(*it, join(path, key));
  }
  std::string string(const json& object, const std::string& path, const char* key) const {
    const json& value = field(object, path, key);
    if (!value.is_string()) fail(join(path, key), "expected a string");
    return value.get<std::string>();
  }
  bool boolean(const json& object, const std::string& path, const char* key) const {
    const json& value = field(object, path, key);
    if (!value.is_boolean()) fail(join(path, key), "expected true or false");
    return value.get<bool>();
  }
  Eigen::Vector3d vector3(const json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers");
    return {number(value[0], path + "[0]"), number(value[1], path + "[1]"),
            number(value[2], path + "[2]")};
  }
  Pose<double> pose(const json& value, const std::string& path) const {
    Pose<double> out;
    const json& rotation = field(value, path, "rotation");
    if (!rotation.is_array() || rotation.size() != 3) fail(path + ".rotation", "expected 3 rows");
    for (int r = 0; r < 3; ++r)
      out.rotation.row(r) = vector3(rotation[r], path + ".rotation[" + std::to_string(r) + "]");
    if ((out.rotation * out.rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
        out.rotation.determinant() < 0.0)
      fail(path + ".rotation", "not a rotation matrix");
    out.translation = vector3(field(value, path, "translation"), path + ".translation");
    return out;
  }
  static std::string join(const std::string& path, const char* key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  std::string file_;
};

}  // namespace

std::string modelToJson(const Model& model) {
  json bodies = json::array();
  for (int i = 0; i < model.numJoints(); ++i) {
    const JointLimits& l = model.limits[i];
    json joint = {{"name", model.joint_names[i]},
                  {"type", jointTypeName(model.joint_types()[i])},
                  {"axis", {model.axes()[i].x(), model.axes()[i].y(), model.axes()[i].z()}},
                  {"placement", poseToJson(model.joint_placements()[i])},
                  {"body_placement", poseToJson(model.body_placements()[i])},
                  {"limits",
                   {{"lower", numberOrNull(l.lower)},
                    {"upper", numberOrNull(l.upper)},
                    {"velocity", numberOrNull(l.velocity)},
                    {"effort", numberOrNull(l.effort)}}}};
    json inertial = json::object();
    const auto theta = toStandardVector(model.inertias()[i]);
    for (int k = 0; k < kLinkParameterCount; ++k)
      inertial[std::string(kLinkParameterNames[k])] = theta(k);
    const DriveParameters<double>& d = model.drives()[i];
    const int p = model.parents()[i];
    bodies.push_back(
        {{"name", model.link_names[i]},
         {"parent", p < 0 ? json(nullptr) : json(model.link_names[p])},
         {"joint", joint},
         {"inertial", inertial},
         {"drive",
          {{"Ia", d.rotor_inertia}, {"Fv", d.viscous}, {"Fc", d.coulomb}, {"Fo", d.offset}}}});
  }
  const json document = {{"schema_version", kModelSchemaVersion},
                         {"kind", "dynid.model"},
                         {"name", model.name},
                         {"gravity", {model.gravity.x(), model.gravity.y(), model.gravity.z()}},
                         {"drives", model.drives_enabled},
                         {"offsets", model.offsets_enabled},
                         {"bodies", bodies}};
  // nlohmann prints doubles with max_digits10, which round-trips exactly.
  return document.dump(2) + "\n";
}

Model modelFromJson(const std::string& text, const std::string& file) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::parse_error& e) {
    throw ParseError(file, 0, "", std::string("invalid JSON: ") + e.what());
  }
  Reader read(file);
  const json& version = read.field(document, "", "schema_version");
  if (!version.is_number_integer() || version.get<int>() != kModelSchemaVersion)
    read.fail("schema_version",
              "unsupported (this dynid reads version " + std::to_string(kModelSchemaVersion) + ")");
  Model model;
  model.name = read.string(document, "", "name");
  model.gravity = read.vector3(read.field(document, "", "gravity"), "gravity");
  model.drives_enabled = read.boolean(document, "", "drives");
  model.offsets_enabled = read.boolean(document, "", "offsets");
  const json& bodies = read.field(document, "", "bodies");
  if (!bodies.is_array() || bodies.empty()) read.fail("bodies", "expected a non-empty array");
  std::map<std::string, int> index_of;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string path = "bodies[" + std::to_string(b) + "]";
    const json& body = bodies[b];
    const std::string name = read.string(body, path, "name");
    if (index_of.count(name)) read.fail(path + ".name", "duplicate body name '" + name + "'");
    const json& parent_json = read.field(body, path, "parent");
    int parent = -1;
    if (!parent_json.is_null()) {
      if (!parent_json.is_string()) read.fail(path + ".parent", "expected a body name or null");
      const auto it = index_of.find(parent_json.get<std::string>());
      if (it == index_of.end())
        read.fail(path + ".parent", "unknown parent '" + parent_json.get<std::string>() +
                                        "' (parents must be listed before their children)");
      parent = it->second;
    }
    const std::string jpath = path + ".joint";
    const json& joint = read.field(body, path, "joint");
    const std::string type_name = read.string(joint, jpath, "type");
    JointType type;
    if (type_name == "revolute")
      type = JointType::kRevolute;
    else if (type_name == "continuous")
      type = JointType::kContinuous;
    else if (type_name == "prismatic")
      type = JointType::kPrismatic;
    else
      read.fail(jpath + ".type",
                "unsupported joint type '" + type_name + "' (revolute, continuous or prismatic)");
    const Eigen::Vector3d axis = read.vector3(read.field(joint, jpath, "axis"), jpath + ".axis");
    if (std::abs(axis.norm() - 1.0) > 1e-9) read.fail(jpath + ".axis", "not a unit vector");
    JointLimits limits;
    if (const auto it = joint.find("limits"); it != joint.end()) {
      const std::string lpath = jpath + ".limits";
      constexpr double inf = std::numeric_limits<double>::infinity();
      limits.lower = read.limit(*it, lpath, "lower", -inf);
      limits.upper = read.limit(*it, lpath, "upper", inf);
      limits.velocity = read.limit(*it, lpath, "velocity", inf);
      limits.effort = read.limit(*it, lpath, "effort", inf);
    }
    const std::string ipath = path + ".inertial";
    const json& inertial = read.field(body, path, "inertial");
    Eigen::Matrix<double, 10, 1> theta;
    for (int k = 0; k < kLinkParameterCount; ++k)
      theta(k) = read.number(inertial, ipath, std::string(kLinkParameterNames[k]).c_str());
    if (theta(0) < 0.0) read.fail(ipath + ".m", "negative mass");
    DriveParameters<double> drive;
    if (const auto it = body.find("drive"); it != body.end()) {
      const std::string dpath = path + ".drive";
      drive.rotor_inertia = read.number(*it, dpath, "Ia");
      drive.viscous = read.number(*it, dpath, "Fv");
      drive.coulomb = read.number(*it, dpath, "Fc");
      drive.offset = read.number(*it, dpath, "Fo");
    }
    index_of[name] = model.addBody(
        parent, name, read.string(joint, jpath, "name"), type,
        read.pose(read.field(joint, jpath, "placement"), jpath + ".placement"), axis,
        read.pose(read.field(joint, jpath, "body_placement"), jpath + ".body_placement"),
        fromStandardVector(theta), limits, drive);
  }
  try {
    model.finalize();
  } catch (const InputError& e) {
    throw ParseError(file, 0, "", e.what());
  }
  return model;
}

}  // namespace dynid
