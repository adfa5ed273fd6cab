// The column names and field rules floating datasets and raw floating logs share
// (data/floating/floating_dataset.hpp, floating_log.hpp): internal to data/floating.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.hpp"

namespace dynid::floating_columns {

constexpr const char* kOrientation[] = {"qw", "qx", "qy", "qz"};
constexpr const char* kTwist[] = {"wx", "wy", "wz", "vx", "vy", "vz"};
constexpr const char* kAcceleration[] = {"dwx", "dwy", "dwz", "dvx", "dvy", "dvz"};
constexpr const char* kJointBlocks[] = {"q", "dq", "ddq", "tau"};
/// An IMU's gyro (rad/s) and accelerometer (specific force, m/s^2) columns, in its frame's axes.
constexpr const char* kImu[] = {"wx", "wy", "wz", "ax", "ay", "az"};
/// A wrench's components in its rows' order (a point's force: the last three).
constexpr const char* kWrench[] = {"nx", "ny", "nz", "fx", "fy", "fz"};

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

/// "a, b, c".
inline std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// The index of `name` among `count` names, or -1.
inline int indexOf(const char* const* names, int count, std::string_view name) {
  for (int k = 0; k < count; ++k)
    if (name == names[k]) return k;
  return -1;
}

/// A field as a finite number; ParseError naming the file, line and column otherwise.
inline double parseField(std::string_view field, const std::string& file, int line,
                         const std::string& column) {
  field = trim(field);
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  double x = 0.0;
  const auto parsed = std::from_chars(field.data(), field.data() + field.size(), x);
  if (field.empty() || parsed.ptr != field.data() + field.size() || parsed.ec != std::errc())
    throw ParseError(file, line, column, "'" + std::string(field) + "' is not a finite number");
  if (!std::isfinite(x))
    throw ParseError(file, line, column, "'" + std::string(field) + "' is not finite");
  return x;
}

}  // namespace dynid::floating_columns
