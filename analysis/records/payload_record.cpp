#include "analysis/records/payload_record.hpp"

#include <array>
#include <cmath>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"

namespace dynid {

Eigen::Matrix<double, 10, 1> payloadBodyFrom(const nlohmann::json& document,
                                             const std::string& file) {
  const std::string kind =
      document.is_object() && document.contains("kind") && document["kind"].is_string()
          ? document["kind"].get<std::string>()
          : "";
  if (kind != kPayloadDocument.kind && kind != kPayloadBodyDocument.kind)
    throw ParseError(file, 0, "kind",
                     "not a payload (expected kind " + std::string(kPayloadDocument.kind) + " or " +
                         kPayloadBodyDocument.kind + ")");
  if (!document.contains("standard") || !document["standard"].is_object())
    throw ParseError(file, 0, "standard", "missing: the payload's standard parameters");
  const nlohmann::json& standard = document["standard"];
  static constexpr std::array<const char*, 10> names = {"m",   "mx",  "my",  "mz",  "Ixx",
                                                        "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
  Eigen::Matrix<double, 10, 1> out;
  for (int k = 0; k < 10; ++k) {
    const char* name = names[static_cast<std::size_t>(k)];
    if (!standard.contains(name) || !standard[name].is_number())
      throw ParseError(file, 0, std::string("standard.") + name, "missing or not a number");
    out[k] = standard[name].get<double>();
    if (!std::isfinite(out[k]))
      throw ParseError(file, 0, std::string("standard.") + name, "not finite");
  }
  return out;
}

}  // namespace dynid
