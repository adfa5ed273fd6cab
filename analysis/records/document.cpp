#include "analysis/records/document.hpp"

#include "data/json_reader.hpp"

namespace dynid {

nlohmann::json documentHeader(const DocumentType& type) {
  return {{"schema_version", type.schema_version}, {"kind", type.kind}};
}

nlohmann::json parseJson(const std::string& text, const std::string& file) {
  return parseJsonDocument(text, file);
}

}  // namespace dynid
