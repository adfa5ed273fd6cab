#include "analysis/records/excitation_record.hpp"

#include <cmath>

#include "analysis/records/document.hpp"
#include "analysis/records/model_source.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

namespace {

/// A `design` object's Fourier series (period, harmonics, offset, a, b, form and `extra` keys; `at`
/// its path in the document) of `rows` rows (0: as many as its offset has), one per `each`
/// ("joint") in `unit` ("rad/s").
FourierSeries fourierSeriesFrom(const JsonReader& read, const nlohmann::json& design,
                                const std::string& at, int rows, std::vector<std::string> extra,
                                const std::string& each, const std::string& unit) {
  extra.insert(extra.end(), {"period", "harmonics", "offset", "a", "b", "form"});
  read.onlyKeysIn(design, at, extra);
  FourierSeries d;
  d.period = read.number(design, at, "period", 1e-6, 1e4);
  const int h = static_cast<int>(read.integer(design, at, "harmonics", 1, 1000));
  d.offset = read.vector(read.field(design, at, "offset"), at + ".offset", rows > 0 ? rows : -1);
  rows = static_cast<int>(d.offset.size());
  for (double x : d.offset)
    if (std::abs(x) > kMaxModelLength) read.fail(at + ".offset", "an offset beyond +-1e6");
  d.a.resize(rows, h);
  d.b.resize(rows, h);
  for (const char* key : {"a", "b"}) {
    const std::string path = at + "." + key;
    const nlohmann::json& table = read.array(read.field(design, at, key), path);
    if (static_cast<int>(table.size()) != rows)
      read.fail(path, "expected " + std::to_string(rows) + " rows (one per " + each + "), not " +
                          std::to_string(table.size()));
    Eigen::MatrixXd& m = key[0] == 'a' ? d.a : d.b;
    for (int j = 0; j < rows; ++j) {
      const std::string row_path = path + "[" + std::to_string(j) + "]";
      const Eigen::VectorXd row = read.vector(table[j], row_path, h);
      for (double x : row)
        if (std::abs(x) > 1e6) read.fail(row_path, "a coefficient beyond +-1e6 " + unit);
      m.row(j) = row.transpose();
    }
  }
  return d;
}

}  // namespace

FourierSeries excitationDesignFrom(const nlohmann::json& document, const std::string& file,
                                   int num_joints) {
  const JsonReader read(file);
  // Version 1 (before payload motions) has no payload_link, and versions 1 and 2 name the model
  // in `model` (a string) where version 3 embeds it (an object, with model_source): their
  // designs read the same.
  const int version = documentVersion(document, kExcitationDocument.schema_version);
  read.header(document, version, kExcitationDocument.kind);
  std::vector<std::string> keys = {"schema_version",
                                   "kind",
                                   "robot",
                                   "model",
                                   "joints",
                                   "design",
                                   "criterion",
                                   "limits",
                                   "base_parameters",
                                   "torque_noise",
                                   "designed",
                                   "default_sinusoid",
                                   "gc_condition_unit",
                                   "check",
                                   "default_sinusoid_check",
                                   "optimiser"};
  if (version >= 2) keys.push_back("payload_link");
  if (version >= 3) keys.push_back("model_source");
  if (version >= 4) keys.push_back("provenance");
  if (version >= 5) keys.push_back("stand");
  read.onlyKeysIn(document, "", keys);
  // The robot designed for, embedded for the record: checked for form, not used (a design is
  // for the --robot it is run on, whose joint count it must have).
  if (version >= 3 && document.contains("model")) read.object(document["model"], "model");
  if (document.contains("model_source"))
    modelSourceFrom(document["model_source"], file, "model_source");
  return fourierSeriesFrom(read, read.field(document, "", "design"), "design", num_joints, {},
                           "joint", "rad/s");
}

FourierSeries readExcitationDesign(const std::string& path, int num_joints) {
  return excitationDesignFrom(parseJsonDocument(readFile(path), path), path, num_joints);
}

std::vector<Eigen::Vector2d> excitationStandTiltsFrom(const nlohmann::json& document,
                                                      const std::string& file) {
  const JsonReader read(file);
  std::vector<Eigen::Vector2d> out;
  const auto at = document.find("stand");
  if (at == document.end() || at->is_null()) return out;
  const nlohmann::json& stand = read.object(*at, "stand");
  read.onlyKeys(stand, "stand",
                {"tilts", "form", "max_tilt", "grid", "samples", "candidates", "criterion",
                 "condition", "condition_added", "exchanges", "sets"});
  const nlohmann::json& tilts = read.array(read.field(stand, "stand", "tilts"), "stand.tilts");
  if (tilts.empty() || tilts.size() > 16)
    read.fail("stand.tilts", "1 to 16 orientations, not " + std::to_string(tilts.size()));
  for (std::size_t k = 0; k < tilts.size(); ++k) {
    const std::string path = "stand.tilts[" + std::to_string(k) + "]";
    const Eigen::VectorXd tilt = read.vector(tilts[k], path, 2);
    if (tilt.cwiseAbs().maxCoeff() > M_PI / 2) read.fail(path, "a roll or pitch beyond +-pi/2 rad");
    out.emplace_back(tilt[0], tilt[1]);
  }
  return out;
}

StandingDesignRecord standingDesignFrom(const nlohmann::json& document, const std::string& file,
                                        int num_joints) {
  const JsonReader read(file);
  read.header(document, documentVersion(document, kStandingExcitationDocument.schema_version),
              kStandingExcitationDocument.kind);
  read.onlyKeys(document, "",
                {"schema_version", "kind", "robot", "model_source", "contacts", "stance", "set",
                 "design", "joint_design", "limits", "designed", "sets", "criterion",
                 "default_sway_problem", "optimiser", "provenance"});
  StandingDesignRecord out;
  out.contacts = read.strings(read.field(document, "", "contacts"), "contacts");
  if (out.contacts.empty()) read.fail("contacts", "a standing robot holds on at least one");
  out.stance =
      read.vector(read.field(document, "", "stance"), "stance", num_joints > 0 ? num_joints : -1);
  for (double x : out.stance)
    if (std::abs(x) > 1e3) read.fail("stance", "a joint beyond +-1000");
  out.base = fourierSeriesFrom(read, read.field(document, "", "design"), "design", 6,
                               {"coordinates"}, "coordinate", "m/s or rad/s");
  if (const auto j = document.find("joint_design"); j != document.end() && !j->is_null())
    out.joints = fourierSeriesFrom(read, *j, "joint_design", static_cast<int>(out.stance.size()),
                                   {}, "joint", "rad/s");
  return out;
}

ExcitationDesignFile readExcitationDesignFile(const std::string& path, int num_joints) {
  const nlohmann::json document = parseJsonDocument(readFile(path), path);
  ExcitationDesignFile out;
  if (isDocumentOfKind(document, kStandingExcitationDocument)) {
    out.standing = standingDesignFrom(document, path, num_joints);
    return out;
  }
  out.design = excitationDesignFrom(document, path, num_joints);
  out.stand_tilts = excitationStandTiltsFrom(document, path);
  return out;
}

}  // namespace dynid
