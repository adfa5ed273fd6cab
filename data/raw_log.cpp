#include "data/raw_log.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> splitFields(const std::string& line, char delimiter) {
  std::vector<std::string> out;
  if (delimiter == ' ') {
    std::istringstream in(line);
    for (std::string f; in >> f;) out.push_back(f);
    return out;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(delimiter, start);
    out.push_back(
        trim(line.substr(start, end == std::string::npos ? std::string::npos : end - start)));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

/// The number in `field`, or false when it is not one (the whole field must parse).
bool parseNumber(const std::string& field, double* out) {
  if (field.empty()) return false;
  std::size_t used = 0;
  try {
    *out = std::stod(field, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == field.size();
}

}  // namespace

RawTable readRawTable(const std::string& path) {
  const std::string text = readFile(path);
  std::istringstream in(text);
  RawTable table;
  table.file = path;
  char delimiter = 0;
  std::vector<std::vector<double>> rows;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    const std::string content = trim(line);
    if (content.empty() || content[0] == '#') continue;
    if (delimiter == 0) {
      delimiter = ' ';
      for (char d : {',', ';', '\t'})
        if (content.find(d) != std::string::npos) {
          delimiter = d;
          break;
        }
    }
    const std::vector<std::string> fields = splitFields(content, delimiter);
    std::vector<double> row(fields.size());
    bool numeric = true;
    for (std::size_t c = 0; c < fields.size(); ++c)
      numeric = numeric && parseNumber(fields[c], &row[c]);
    if (table.names.empty() && rows.empty()) {
      if (!numeric) {  // a header
        table.names = fields;
        continue;
      }
      for (std::size_t c = 0; c < fields.size(); ++c) table.names.push_back(std::to_string(c + 1));
    }
    if (rows.empty()) table.first_data_line = line_number;
    if (fields.size() != table.names.size())
      throw ParseError(path, line_number, "",
                       "has " + std::to_string(fields.size()) + " fields, the table has " +
                           std::to_string(table.names.size()) + " columns");
    for (std::size_t c = 0; c < fields.size(); ++c)
      if (!parseNumber(fields[c], &row[c]) || !std::isfinite(row[c]))
        throw ParseError(path, line_number, table.names[c],
                         "'" + fields[c] + "' is not a finite number");
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw ParseError(path, 0, "", "has no data rows");
  table.values.resize(static_cast<Eigen::Index>(rows.size()),
                      static_cast<Eigen::Index>(table.names.size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < rows[r].size(); ++c)
      table.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
  return table;
}

Eigen::MatrixXd readValueFile(const std::string& path, int width) {
  const std::string text = readFile(path);
  std::istringstream in(text);
  std::vector<double> values;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    std::istringstream fields(line);
    for (std::string field; fields >> field;) {
      double x = 0.0;
      if (!parseNumber(field, &x) || !std::isfinite(x))
        throw ParseError(path, line_number, "", "'" + field + "' is not a finite number");
      values.push_back(x);
    }
  }
  if (values.empty()) throw ParseError(path, 0, "", "has no values");
  if (values.size() % static_cast<std::size_t>(width) != 0)
    throw ParseError(path, 0, "",
                     "has " + std::to_string(values.size()) + " values, not a multiple of " +
                         std::to_string(width) + " (one per joint per sample)");
  const auto rows = static_cast<Eigen::Index>(values.size() / static_cast<std::size_t>(width));
  Eigen::MatrixXd out(rows, width);
  for (Eigen::Index r = 0; r < rows; ++r)
    for (int c = 0; c < width; ++c) out(r, c) = values[static_cast<std::size_t>(r * width + c)];
  return out;
}

std::vector<int> selectColumns(const RawTable& table, const std::string& selector, int expected,
                               const std::string& what) {
  std::vector<int> out;
  for (const std::string& entry : splitFields(selector, ',')) {
    if (entry.empty())
      throw ParseError(table.file, 0, what, "an empty column entry in '" + selector + "'");
    std::vector<int> matched;
    double index = 0.0;
    if (parseNumber(entry, &index) && index == std::floor(index)) {
      if (index < 1 || index > static_cast<double>(table.names.size()))
        throw ParseError(
            table.file, 0, what,
            "column " + entry + " is out of range (1.." + std::to_string(table.names.size()) + ")");
      matched.push_back(static_cast<int>(index) - 1);
    } else {
      for (std::size_t c = 0; c < table.names.size(); ++c)
        if (fnmatch(entry.c_str(), table.names[c].c_str(), 0) == 0)
          matched.push_back(static_cast<int>(c));
    }
    if (matched.empty()) {
      std::string list;
      for (const std::string& n : table.names) {
        if (!list.empty()) list += ", ";
        list += n;
      }
      throw ParseError(table.file, 0, what,
                       "'" + entry + "' matches no column (columns: " + list + ")");
    }
    for (int c : matched) {
      if (std::find(out.begin(), out.end(), c) != out.end())
        throw ParseError(table.file, 0, what, "column '" + table.names[c] + "' is matched twice");
      out.push_back(c);
    }
  }
  if (expected >= 0 && static_cast<int>(out.size()) != expected)
    throw ParseError(table.file, 0, what,
                     "'" + selector + "' matches " + std::to_string(out.size()) +
                         " columns, expected " + std::to_string(expected));
  return out;
}

}  // namespace dynid
