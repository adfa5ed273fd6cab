// The one JSON-number convention of dynid's documents: JSON has no infinity or NaN, so a
// non-finite number is written as null (and read back as NaN, or as the field's documented
// meaning, e.g. an unlimited joint limit).
#pragma once

#include <cmath>

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

/// A number, or NaN for null (the inverse of numberOrNull).
inline double numberOrNan(const nlohmann::json& j) {
  return j.is_null() ? std::nan("") : j.get<double>();
}

}  // namespace dynid
