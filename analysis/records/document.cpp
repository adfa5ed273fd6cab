#include "analysis/records/document.hpp"

#include "data/json_reader.hpp"

namespace dynid {

nlohmann::json documentHeader(const DocumentType& type) {
  return {{"schema_version", type.schema_version}, {"kind", type.kind}};
}

nlohmann::json parseJson(const std::string& text, const std::string& file) {
  return parseJsonDocument(text, file);
}

int documentVersion(const nlohmann::json& document, int current) {
  if (document.is_object() && document.contains("schema_version") &&
      document["schema_version"].is_number_integer() && document["schema_version"] >= 1 &&
      document["schema_version"] < current)
    return document["schema_version"].get<int>();
  return current;
}

bool isDocumentOfKind(const nlohmann::json& document, const DocumentType& type) {
  return document.is_object() && document.contains("kind") && document["kind"].is_string() &&
         document["kind"].get<std::string>() == type.kind;
}

}  // namespace dynid
