// The conventions of the JSON documents dynid writes: JSON has no infinity or NaN, so a
// non-finite number is written as null (and read back as NaN, or as the field's documented
// meaning, e.g. an unlimited joint limit); text that is not UTF-8 is replaced, never fatal.
#pragma once

#include <cmath>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace dynid {

/// x, or null when x is not finite.
inline nlohmann::json numberOrNull(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

/// [v_0, v_1, ...], each entry through numberOrNull.
inline nlohmann::json numbersOrNull(const Eigen::VectorXd& v) {
  nlohmann::json out = nlohmann::json::array();
  for (double x : v) out.push_back(numberOrNull(x));
  return out;
}

/// The text of a JSON document dynid writes (`indent` < 0: one line). A string that is not valid
/// UTF-8 (a file path in another encoding) has its bad bytes replaced by U+FFFD rather than
/// failing the write: names read from files are checked at the boundary, paths cannot be.
inline std::string jsonText(const nlohmann::json& document, int indent = -1) {
  return document.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// A number, or NaN for null (the inverse of numberOrNull).
inline double numberOrNan(const nlohmann::json& j) {
  return j.is_null() ? std::nan("") : j.get<double>();
}

}  // namespace dynid
