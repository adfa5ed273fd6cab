// The column names and field rules floating datasets and raw floating logs share
// (data/floating/floating_dataset.hpp, floating_log.hpp): internal to data/floating.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.hpp"
#include "data/io.hpp"

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

/// A named-column table read row by row: its header's names (trimmed), then each row that is not
/// blank, as many fields as the header has (else a ParseError naming the line).
class ColumnTable {
 public:
  /// Throws ParseError when the file has no header (`what`: "a floating dataset").
  ColumnTable(const std::string& path, const char* what) : lines_(path), path_(path) {
    std::string_view line;
    if (!lines_.next(line) || trim(line).empty())
      throw ParseError(path, 1, "",
                       std::string("no header: ") + what + " starts with its column names");
    header_ = splitFields(line);
    for (std::string_view f : header_) names_.emplace_back(trim(f));
  }
  const std::vector<std::string>& names() const { return names_; }
  /// The header's fields as read (valid until the first next()).
  const std::vector<std::string_view>& headerFields() const { return header_; }
  /// The next row's fields into `fields` (views valid until the next call); false at the end.
  bool next(std::vector<std::string_view>& fields) {
    std::string_view line;
    while (lines_.next(line)) {
      if (trim(line).empty()) continue;
      fields = splitFields(line);
      if (fields.size() != names_.size())
        throw ParseError(path_, lines_.lineNumber(), "",
                         "row has " + std::to_string(fields.size()) + " fields, the header has " +
                             std::to_string(names_.size()));
      return true;
    }
    return false;
  }
  int line() const { return lines_.lineNumber(); }

 private:
  LineReader lines_;
  std::string path_;
  std::vector<std::string_view> header_;
  std::vector<std::string> names_;
};

}  // namespace dynid::floating_columns
