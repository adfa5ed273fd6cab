// Where the robot a document embeds came from (estimate.json, prediction.json, payload.json,
// thresholds.json, excitation.json): the robot spec as given, the file's name and its SHA-256, so
// that a reader of the document can tell the file it has from the one the document used. Written
// as "model_source": {"spec", "file", "sha256"} beside the embedded "model" (reports/).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace dynid {

struct ModelSource {
  std::string spec;    // as given: a built-in name ("puma560") or a path
  std::string file;    // the file's name without its folder; empty for a built-in robot
  std::string sha256;  // the file's SHA-256, 64 lowercase hex digits; empty for a built-in robot
};

/// The source of robot `spec` as it is now: for a file, its name and SHA-256 (data/digest); for a
/// built-in robot, the spec alone. Throws InputError when the file cannot be read.
ModelSource modelSourceOf(const std::string& spec);

/// model_source as documents write it: {spec, file, sha256}, the last two null for a built-in
/// robot.
nlohmann::json modelSourceJson(const ModelSource& source);

/// A robot spec a document recorded as typed where it was made: as it is when it names a built-in
/// robot or a file found from here, else relative to the document's folder when a file is found
/// there (a document's own relative paths are its folder's).
std::string specBesideDocument(const std::string& spec, const std::string& document_file);

/// model_source of a document (`path` names it in messages, "model_source"): an object with
/// exactly spec, file and sha256, the last two null or strings, sha256 64 lowercase hex digits.
/// Throws ParseError naming `file` and the field.
ModelSource modelSourceFrom(const nlohmann::json& value, const std::string& file,
                            const std::string& path);

}  // namespace dynid
