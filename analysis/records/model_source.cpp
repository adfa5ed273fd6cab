#include "analysis/records/model_source.hpp"

#include <filesystem>

#include "data/digest/sha256.hpp"
#include "data/json_reader.hpp"

namespace dynid {

ModelSource modelSourceOf(const std::string& spec) {
  ModelSource out{spec, "", ""};
  std::error_code error;
  if (std::filesystem::is_regular_file(spec, error)) {
    out.file = std::filesystem::path(spec).filename().string();
    out.sha256 = sha256OfFile(spec);
  }
  return out;
}

nlohmann::json modelSourceJson(const ModelSource& source) {
  const auto orNull = [](const std::string& s) {
    return s.empty() ? nlohmann::json() : nlohmann::json(s);
  };
  return {{"spec", source.spec}, {"file", orNull(source.file)}, {"sha256", orNull(source.sha256)}};
}

std::string specBesideDocument(const std::string& spec, const std::string& document_file) {
  std::error_code error;
  const std::filesystem::path path(spec);
  if (path.is_absolute() || std::filesystem::exists(path, error)) return spec;
  const std::filesystem::path beside = std::filesystem::path(document_file).parent_path() / path;
  return std::filesystem::is_regular_file(beside, error) ? beside.string() : spec;
}

ModelSource modelSourceFrom(const nlohmann::json& value, const std::string& file,
                            const std::string& path) {
  const JsonReader read(file);
  const nlohmann::json& source = read.object(value, path);
  read.onlyKeys(source, path, {"spec", "file", "sha256"});
  ModelSource out;
  out.spec = read.string(source, path, "spec");
  if (!read.field(source, path, "file").is_null()) out.file = read.string(source, path, "file");
  if (!read.field(source, path, "sha256").is_null()) {
    out.sha256 = read.string(source, path, "sha256");
    if (out.sha256.size() != 64 ||
        out.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
      read.fail(path + ".sha256", "expected 64 lowercase hexadecimal digits");
  }
  return out;
}

}  // namespace dynid
