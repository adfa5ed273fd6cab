#include "data/model_json.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <Eigen/LU>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/parameters.hpp"
#include "data/dh.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"

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

/// A joint's drive object: every term of the drive-term table by name, enabled or not.
json driveJson(const DriveParameters<double>& d) {
  json out = json::object();
  for (int k = 0; k < kDriveTermCount; ++k) out[std::string(kDriveParameterNames[k])] = d.term(k);
  return out;
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
  /// A name (robot, link, joint): a string of printable UTF-8, since names go into dynid's JSON,
  /// URDF, MJCF and HTML outputs (a control character would make an exported URDF unreadable).
  std::string name(const json& object, const std::string& path, const char* key) const {
    std::string text = string(object, path, key);
    if (!isPrintableUtf8(text)) fail(join(path, key), "contains a control character");
    return text;
  }
  /// Fails when `name` was already used by another link (or joint): `seen` collects them.
  void unique(std::set<std::string>& seen, const std::string& name, const std::string& path,
              const char* what) const {
    if (!seen.insert(name).second)
      fail(path, std::string("duplicate ") + what + " name '" + name + "'");
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
    if (out.translation.cwiseAbs().maxCoeff() > kMaxModelLength)
      fail(path + ".translation", "beyond +-1e6 m");
    return out;
  }
  /// Fails unless every standard parameter is within +-kMaxParameterMagnitude (core/parameters).
  void parameterMagnitudes(const Eigen::Matrix<double, 10, 1>& theta,
                           const std::string& path) const {
    for (int k = 0; k < kLinkParameterCount; ++k)
      if (std::abs(theta(k)) > kMaxParameterMagnitude)
        fail(path, std::string(kLinkParameterNames[k]) + " = " + formatNumber(theta(k)) +
                       " is beyond +-1e6 (SI units: kg, kg m, kg m^2)");
  }
  /// Fails on a key of `object` that is not in `allowed` (a misspelt key must not pass silently).
  void onlyKeys(const json& object, const std::string& path,
                std::initializer_list<const char*> allowed) const {
    JsonReader(file_).onlyKeys(object, path, allowed);
  }
  JointLimits limits(const json& object, const std::string& path) const {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (!object.is_object()) fail(path, "expected an object");
    onlyKeys(object, path, {"lower", "upper", "velocity", "acceleration", "effort"});
    JointLimits out;
    out.lower = limit(object, path, "lower", -inf);
    out.upper = limit(object, path, "upper", inf);
    out.velocity = limit(object, path, "velocity", inf);
    out.acceleration = limit(object, path, "acceleration", inf);
    out.effort = limit(object, path, "effort", inf);
    if (out.lower > out.upper) fail(path, "lower is above upper");
    return out;
  }
  /// A drive object: any of the drive-term table's names, Ia, Fv, ... (a missing one is 0).
  DriveParameters<double> drive(const json& object, const std::string& path) const {
    if (!object.is_object()) fail(path, "expected an object");
    JsonReader(file_).onlyKeysIn(object, path, kDriveParameterNames);
    DriveParameters<double> out;
    for (int k = 0; k < kDriveTermCount; ++k) {
      const std::string key(kDriveParameterNames[k]);
      if (const auto it = object.find(key); it != object.end()) {
        out.term(k) = number(*it, join(path, key.c_str()));
        if (std::abs(out.term(k)) > kMaxParameterMagnitude)
          fail(join(path, key.c_str()), formatNumber(out.term(k)) + " is beyond +-1e6 (SI units)");
      }
    }
    return out;
  }
  /// The document's drive terms: "drive_terms": ["fv", "fc", "fo"] (or [] / absent: none). The
  /// older "drives": true means ["ia", "fv", "fc"]; the older "offsets": true (an asymmetric
  /// Coulomb term then called Fo) is refused with the new spelling.
  DriveTerms driveTerms(const json& document) const {
    if (document.contains("drive_terms") &&
        (document.contains("drives") || document.contains("offsets")))
      fail("drive_terms",
           "give either \"drive_terms\" or the older \"drives\"/\"offsets\", not both");
    if (document.contains("offsets") && boolean(document, "", "offsets"))
      fail("offsets",
           "\"offsets\" is no longer read: the asymmetric Coulomb term is now \"fa\" (value "
           "\"Fa\"); write \"drive_terms\": [\"ia\", \"fv\", \"fc\", \"fa\"] and rename each "
           "drive's \"Fo\" to \"Fa\" (\"fo\"/\"Fo\" is now a constant offset)");
    if (document.contains("drives"))
      return boolean(document, "", "drives") ? DriveTerms::rotorAndFriction() : DriveTerms::none();
    const auto it = document.find("drive_terms");
    if (it == document.end()) return {};
    if (!it->is_array())
      fail("drive_terms", "expected an array of term names (" + driveTermKeyList() + ")");
    std::string list;
    for (std::size_t k = 0; k < it->size(); ++k) {
      const json& term = (*it)[k];
      if (!term.is_string())
        fail("drive_terms[" + std::to_string(k) + "]",
             "expected a term name (" + driveTermKeyList() + ")");
      if (!list.empty()) list += ',';
      list += term.get<std::string>();
    }
    if (list.empty()) return {};
    try {
      return parseDriveTerms(list);
    } catch (const InputError& e) {
      fail("drive_terms", e.what());
    }
  }
  JointType jointType(const json& object, const std::string& path) const {
    const std::string name = string(object, path, "type");
    if (name == "revolute") return JointType::kRevolute;
    if (name == "continuous") return JointType::kContinuous;
    if (name == "prismatic") return JointType::kPrismatic;
    fail(join(path, "type"),
         "unsupported joint type '" + name + "' (revolute, continuous or prismatic)");
  }
  static std::string join(const std::string& path, const char* key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  std::string file_;
};

/// The inertial block of a DH row: the standard 10 about the link frame origin, or
/// {"m", "com": [3], "inertia": {"Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"}} about the centre of
/// mass.
RigidInertia<double> dhInertia(const json& inertial, const std::string& path, bool at_com,
                               const Reader& read) {
  if (!at_com) {
    read.onlyKeys(inertial, path,
                  {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"});
    Eigen::Matrix<double, 10, 1> theta;
    for (int k = 0; k < kLinkParameterCount; ++k)
      theta(k) = read.number(inertial, path, std::string(kLinkParameterNames[k]).c_str());
    if (theta(0) < 0.0) read.fail(path + ".m", "negative mass");
    read.parameterMagnitudes(theta, path);
    return fromStandardVector(theta);
  }
  read.onlyKeys(inertial, path, {"m", "com", "inertia"});
  const double mass = read.number(inertial, path, "m");
  if (mass < 0.0) read.fail(path + ".m", "negative mass");
  const Eigen::Vector3d com = read.vector3(read.field(inertial, path, "com"), path + ".com");
  const std::string ipath = path + ".inertia";
  const json& I = read.field(inertial, path, "inertia");
  read.onlyKeys(I, ipath, {"Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"});
  Eigen::Matrix3d about_com;
  about_com(0, 0) = read.number(I, ipath, "Ixx");
  about_com(0, 1) = about_com(1, 0) = read.number(I, ipath, "Ixy");
  about_com(0, 2) = about_com(2, 0) = read.number(I, ipath, "Ixz");
  about_com(1, 1) = read.number(I, ipath, "Iyy");
  about_com(1, 2) = about_com(2, 1) = read.number(I, ipath, "Iyz");
  about_com(2, 2) = read.number(I, ipath, "Izz");
  const RigidInertia<double> out = inertiaFromCom(mass, com, about_com);
  read.parameterMagnitudes(toStandardVector(out), path);
  return out;
}

/// A model from the document's "dh" block (data/dh.hpp); `model` carries the common fields.
Model dhModelFromJson(const json& document, const Model& model, const Reader& read,
                      const std::string& file) {
  const json& block = read.field(document, "", "dh");
  read.onlyKeys(block, "dh", {"convention", "inertia_about", "joints"});
  DhModel dh;
  dh.name = model.name;
  dh.gravity = model.gravity();
  dh.drive_terms = model.driveTerms();
  const std::string convention = read.string(block, "dh", "convention");
  if (convention != "standard" && convention != "modified")
    read.fail("dh.convention", "unknown convention '" + convention + "' (standard or modified)");
  dh.convention = convention == "standard" ? DhConvention::kStandard : DhConvention::kModified;
  const std::string about = read.string(block, "dh", "inertia_about");
  if (about != "com" && about != "origin")
    read.fail("dh.inertia_about",
              "must be \"com\" (centre of mass) or \"origin\" (link frame "
              "origin), not '" +
                  about + "'");
  const json& joints = read.field(block, "dh", "joints");
  if (!joints.is_array() || joints.empty()) read.fail("dh.joints", "expected a non-empty array");
  std::set<std::string> joint_names, link_names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const std::string path = "dh.joints[" + std::to_string(i) + "]";
    const json& j = joints[i];
    read.onlyKeys(
        j, path,
        {"name", "link", "type", "a", "d", "alpha", "theta_offset", "limits", "inertial", "drive"});
    DhRow row;
    row.joint_name = read.name(j, path, "name");
    row.link_name = read.name(j, path, "link");
    read.unique(joint_names, row.joint_name, path + ".name", "joint");
    read.unique(link_names, row.link_name, path + ".link", "link");
    row.type = read.jointType(j, path);
    row.a = read.number(j, path, "a");
    row.d = read.number(j, path, "d");
    if (std::abs(row.a) > kMaxModelLength || std::abs(row.d) > kMaxModelLength)
      read.fail(path, "a or d beyond +-1e6 m");
    row.alpha = read.number(j, path, "alpha");
    row.theta_offset = j.contains("theta_offset") ? read.number(j, path, "theta_offset") : 0.0;
    if (const auto it = j.find("limits"); it != j.end())
      row.limits = read.limits(*it, path + ".limits");
    row.inertia =
        dhInertia(read.field(j, path, "inertial"), path + ".inertial", about == "com", read);
    if (const auto it = j.find("drive"); it != j.end())
      row.drive = read.drive(*it, path + ".drive");
    dh.rows.push_back(row);
  }
  try {
    return modelFromDh(dh);
  } catch (const InputError& e) {
    throw ParseError(file, 0, "dh", e.what());
  }
}

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
                    {"acceleration", numberOrNull(l.acceleration)},
                    {"effort", numberOrNull(l.effort)}}}};
    json inertial = json::object();
    const auto theta = toStandardVector(model.inertias()[i]);
    for (int k = 0; k < kLinkParameterCount; ++k)
      inertial[std::string(kLinkParameterNames[k])] = theta(k);
    const DriveParameters<double>& d = model.drives()[i];
    const int p = model.parents()[i];
    bodies.push_back({{"name", model.link_names[i]},
                      {"parent", p < 0 ? json(nullptr) : json(model.link_names[p])},
                      {"joint", joint},
                      {"inertial", inertial},
                      {"drive", driveJson(d)}});
  }
  const json document = {
      {"schema_version", kModelSchemaVersion},
      {"kind", "dynid.model"},
      {"name", model.name},
      {"gravity", {model.gravity().x(), model.gravity().y(), model.gravity().z()}},
      {"drive_terms", driveTermsKeys(model.driveTerms())},
      {"bodies", bodies}};
  // nlohmann prints doubles with max_digits10, which round-trips exactly.
  return jsonText(document, 2) + "\n";
}

Model modelFromJson(const std::string& text, const std::string& file) {
  const json document = parseJsonDocument(text, file);
  Reader read(file);
  const json& version = read.field(document, "", "schema_version");
  if (!version.is_number_integer() || version != kModelSchemaVersion)
    read.fail("schema_version",
              "unsupported (this dynid reads version " + std::to_string(kModelSchemaVersion) + ")");
  read.onlyKeys(document, "",
                {"schema_version", "kind", "name", "gravity", "drive_terms", "drives", "offsets",
                 "bodies", "dh"});
  if (document.contains("kind") && document["kind"] != "dynid.model")
    read.fail("kind", "must be \"dynid.model\", not " + document["kind"].dump());
  if (document.contains("dh") == document.contains("bodies"))
    read.fail("", "give the kinematics as either \"bodies\" or \"dh\", not both or neither");
  Model model;
  model.name = read.name(document, "", "name");
  const Eigen::Vector3d gravity = read.vector3(read.field(document, "", "gravity"), "gravity");
  if (gravity.norm() > kMaxGravity) read.fail("gravity", "beyond 1e3 m/s^2");
  model.setGravity(gravity);
  model.setDriveTerms(read.driveTerms(document));
  if (document.contains("dh")) return dhModelFromJson(document, model, read, file);
  const json& bodies = read.field(document, "", "bodies");
  if (!bodies.is_array() || bodies.empty()) read.fail("bodies", "expected a non-empty array");
  std::map<std::string, int> index_of;
  std::set<std::string> joint_names;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string path = "bodies[" + std::to_string(b) + "]";
    const json& body = bodies[b];
    read.onlyKeys(body, path, {"name", "parent", "joint", "inertial", "drive"});
    const std::string name = read.name(body, path, "name");
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
    read.onlyKeys(joint, jpath, {"name", "type", "axis", "placement", "body_placement", "limits"});
    const JointType type = read.jointType(joint, jpath);
    const Eigen::Vector3d axis = read.vector3(read.field(joint, jpath, "axis"), jpath + ".axis");
    if (std::abs(axis.norm() - 1.0) > 1e-9) read.fail(jpath + ".axis", "not a unit vector");
    JointLimits limits;
    if (const auto it = joint.find("limits"); it != joint.end())
      limits = read.limits(*it, jpath + ".limits");
    const std::string ipath = path + ".inertial";
    const json& inertial = read.field(body, path, "inertial");
    read.onlyKeys(inertial, ipath,
                  {"m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"});
    Eigen::Matrix<double, 10, 1> theta;
    for (int k = 0; k < kLinkParameterCount; ++k)
      theta(k) = read.number(inertial, ipath, std::string(kLinkParameterNames[k]).c_str());
    if (theta(0) < 0.0) read.fail(ipath + ".m", "negative mass");
    read.parameterMagnitudes(theta, ipath);
    DriveParameters<double> drive;
    if (const auto it = body.find("drive"); it != body.end())
      drive = read.drive(*it, path + ".drive");
    const std::string joint_name = read.name(joint, jpath, "name");
    read.unique(joint_names, joint_name, jpath + ".name", "joint");
    index_of[name] = model.addBody(
        parent, name, joint_name, type,
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
