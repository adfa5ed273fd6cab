#include "analysis/records/document.hpp"

#include "data/json_reader.hpp"

namespace dynid {

nlohmann::json documentHeader(const DocumentType& type) {
  return {{"schema_version", type.schema_version}, {"kind", type.kind}};
}

nlohmann::json parseJson(const std::string& text, const std::string& file) {
  return parseJsonDocument(text, file);
}

bool isDocumentOfKind(const nlohmann::json& document, const DocumentType& type) {
  return document.is_object() && document.contains("kind") && document["kind"].is_string() &&
         document["kind"].get<std::string>() == type.kind;
}

}  // namespace dynid
