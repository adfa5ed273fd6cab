#include "analysis/logs/raw_log.hpp"

#include <fnmatch.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/memory.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
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

/// The number in [begin, end) (blanks around it allowed, a leading '+' too), or false. T: double,
/// or long double for a time stamp read whole (nanosecond epochs need 64 bits).
template <class T>
bool parseNumber(const char* begin, const char* end, T* out) {
  while (begin < end && (*begin == ' ' || *begin == '\t' || *begin == '\r')) ++begin;
  while (end > begin && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r')) --end;
  if (begin < end && *begin == '+') ++begin;
  if (begin == end) return false;
  const auto result = std::from_chars(begin, end, *out);
  return result.ec == std::errc() && result.ptr == end;
}

/// parseNumber, with a ',' in [begin, end) read as the decimal point when `comma` (fields longer
/// than any number, 64 characters, are not numbers).
template <class T>
bool parseNumber(const char* begin, const char* end, bool comma, T* out) {
  if (!comma) return parseNumber(begin, end, out);
  char copy[64];
  const auto length = static_cast<std::size_t>(end - begin);
  if (length > sizeof copy) return false;
  std::replace_copy(begin, end, copy, ',', '.');
  return parseNumber(copy, copy + length, out);
}

/// Whether a field that is not a number would be one with its one ',' read as a decimal point.
bool isDecimalCommaNumber(const char* begin, const char* end) {
  double x = 0.0;
  return std::count(begin, end, ',') == 1 && parseNumber(begin, end, true, &x);
}

/// Reads stamps relative to the first: the first one read becomes the origin, every one is stored
/// as its difference from it (exact for nanosecond epochs, which a double rounds to 256 ns).
struct RelativeStamps {
  long double* origin = nullptr;  // null: stamps are read as plain doubles
  bool comma = false;             // ',' is the decimal point
  bool started = false;
  bool read(const char* begin, const char* end, double* out) {
    if (origin == nullptr) return parseNumber(begin, end, comma, out);
    long double x = 0.0L;
    if (!parseNumber(begin, end, comma, &x) || !std::isfinite(x)) return false;
    if (!started) *origin = x, started = true;
    *out = static_cast<double>(x - *origin);
    return true;
  }
};

/// Calls f(begin, end, line_number) for each line of the file, without its newline, reading it in
/// blocks (memory independent of the file's size); stops when f returns false.
/// Logs are regular files, read twice (count, then parse): anything else (a FIFO nobody writes
/// would block the open for ever, a device never ends) is refused before it is opened.
template <class F>
void forEachLine(const std::string& path, F f) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw ParseError(path, 0, "",
                     S_ISDIR(st.st_mode)
                         ? "is a directory, not a log file"
                         : "is not a regular file: a log is read twice (count, then parse); save "
                           "the stream to a file first");
  LineReader reader(path);
  std::string_view line;
  while (reader.next(line))
    if (!f(line.data(), line.data() + line.size(), reader.lineNumber())) return;
}

/// Whether a field is a missing value: empty (blanks only), or nan or inf in any case and sign.
bool isMissing(const char* begin, const char* end) {
  while (begin < end && (*begin == ' ' || *begin == '\t' || *begin == '\r')) ++begin;
  while (end > begin && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r')) --end;
  if (begin < end && (*begin == '+' || *begin == '-')) ++begin;
  std::string word(begin, end);
  for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return word.empty() || word == "nan" || word == "inf" || word == "infinity";
}

/// Whether the line holds data: not blank, not a '#' comment.
bool isDataLine(const char* begin, const char* end) {
  while (begin < end && (*begin == ' ' || *begin == '\t' || *begin == '\r')) ++begin;
  return begin < end && *begin != '#';
}

/// Calls f(field_begin, field_end) for each field of a line: split at `delimiter`, or at runs of
/// blanks when it is ' '. Returns the number of fields.
template <class F>
int forEachField(const char* begin, const char* end, char delimiter, F f) {
  int count = 0;
  if (delimiter == ' ') {
    const char* p = begin;
    while (true) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      if (p == end) return count;
      const char* q = p;
      while (q < end && *q != ' ' && *q != '\t' && *q != '\r') ++q;
      f(p, q, count++);
      p = q;
    }
  }
  const char* p = begin;
  while (true) {
    const char* q =
        static_cast<const char*>(std::memchr(p, delimiter, static_cast<std::size_t>(end - p)));
    f(p, q == nullptr ? end : q, count++);
    if (q == nullptr) return count;
    p = q + 1;
  }
}

}  // namespace

RawTable readRawHeader(const std::string& path, bool decimal_comma) {
  RawTable table;
  table.file = path;
  table.decimal_comma = decimal_comma;
  bool header_seen = false;
  forEachLine(path, [&](const char* begin, const char* end, int line) {
    if (!isDataLine(begin, end)) return true;
    if (table.delimiter == 0) {
      table.delimiter = ' ';
      for (char d : {',', ';', '\t'})
        if ((!decimal_comma || d != ',') &&
            std::memchr(begin, d, static_cast<std::size_t>(end - begin)) != nullptr) {
          table.delimiter = d;
          break;
        }
      if (decimal_comma && table.delimiter == ' ' &&
          std::memchr(begin, ',', static_cast<std::size_t>(end - begin)) != nullptr &&
          std::memchr(begin, ' ', static_cast<std::size_t>(end - begin)) == nullptr)
        throw ParseError(path, line, "",
                         "`decimal_comma`: the fields are separated by ',' (a decimal comma "
                         "needs ';', tab or blanks between fields)");
      std::vector<std::string> fields;
      bool numeric = true;
      forEachField(begin, end, table.delimiter, [&](const char* b, const char* e, int) {
        double x = 0.0;
        numeric = numeric && parseNumber(b, e, decimal_comma, &x);
        fields.push_back(trim(std::string(b, e)));
      });
      if (!numeric) {
        table.names = fields;
        header_seen = true;
        return true;  // the data start on a later line
      }
      for (std::size_t c = 0; c < fields.size(); ++c) table.names.push_back(std::to_string(c + 1));
    }
    table.first_data_line = line;
    return false;
  });
  if (table.first_data_line == 0) throw ParseError(path, 0, "", "has no data rows");
  (void)header_seen;
  return table;
}

Eigen::MatrixXd readRawColumns(const RawTable& header, const std::vector<int>& columns,
                               long double* time_origin, std::vector<Eigen::Index>* skipped,
                               std::vector<int>* skipped_lines, ScratchColumns* spill) {
  const std::string& path = header.file;
  const auto width = static_cast<int>(header.names.size());
  // Pass 1: the rows, to allocate once.
  Eigen::Index rows = 0;
  forEachLine(path, [&](const char* begin, const char* end, int line) {
    if (line >= header.first_data_line && isDataLine(begin, end)) ++rows;
    return true;
  });
  // Where each table column goes (-1: not kept).
  std::vector<int> target(static_cast<std::size_t>(width), -1);
  for (std::size_t k = 0; k < columns.size(); ++k)
    target.at(static_cast<std::size_t>(columns[k])) = static_cast<int>(k);
  const auto kept = static_cast<Eigen::Index>(columns.size());
  if (spill == nullptr)
    requireMemory(
        static_cast<double>(rows) * static_cast<double>(kept) * sizeof(double),
        path + ": " + std::to_string(rows) + " rows of " + std::to_string(kept) + " columns");
  // With a spill, the rows are parsed into a block, and each full block's first column goes into
  // `values`, the others into the spill.
  Eigen::MatrixXd values(rows, spill != nullptr ? 1 : kept);
  Eigen::MatrixXd block;
  Eigen::Index block_first = 0;  // the block's first row
  if (spill != nullptr)
    block.resize(std::min<Eigen::Index>(rows, ScratchColumns::kBlockRows), kept);
  const auto flush = [&](Eigen::Index end) {
    if (spill == nullptr || end == block_first) return;
    const Eigen::Index count = end - block_first;
    values.col(0).segment(block_first, count) = block.col(0).head(count);
    for (Eigen::Index c = 1; c < kept; ++c)
      spill->write(static_cast<int>(c) - 1, block_first, block.col(c).data(), count);
    block_first = end;
  };
  Eigen::Index row = 0, data_row = 0;
  RelativeStamps stamps{time_origin, header.decimal_comma};
  forEachLine(path, [&](const char* begin, const char* end, int line) {
    if (line < header.first_data_line || !isDataLine(begin, end)) return true;
    if (data_row == rows)
      throw ParseError(path, line, "",
                       "the file grew while being read (" + std::to_string(rows) +
                           " rows when counted): read a finished log");
    bool missing = false;
    const int fields =
        forEachField(begin, end, header.delimiter, [&](const char* b, const char* e, int c) {
          if (c >= width || target[static_cast<std::size_t>(c)] < 0 || missing) return;
          double x = 0.0;
          const bool stamp = target[static_cast<std::size_t>(c)] == 0 && time_origin != nullptr;
          if (!(stamp ? stamps.read(b, e, &x) : parseNumber(b, e, header.decimal_comma, &x)) ||
              !std::isfinite(x)) {
            if (skipped != nullptr && isMissing(b, e)) {
              missing = true;
              return;
            }
            std::string hint;
            if (skipped == nullptr && isMissing(b, e))
              hint = " (a logger's dropout? `skip_missing` leaves such rows out)";
            else if (!header.decimal_comma && header.delimiter != ',' && isDecimalCommaNumber(b, e))
              hint = " (',' for the decimal point? `decimal_comma` reads it)";
            throw ParseError(path, line, header.names[static_cast<std::size_t>(c)],
                             "'" + trim(std::string(b, e)) + "' is not a finite number" + hint);
          }
          if (spill != nullptr)
            block(row - block_first, target[static_cast<std::size_t>(c)]) = x;
          else
            values(row, target[static_cast<std::size_t>(c)]) = x;
        });
    if (fields != width)
      throw ParseError(path, line, "",
                       "has " + std::to_string(fields) + " fields, the table has " +
                           std::to_string(width) + " columns");
    if (missing) {
      skipped->push_back(data_row);
      if (skipped_lines != nullptr) skipped_lines->push_back(line);
    } else {
      ++row;
      if (spill != nullptr && row - block_first == block.rows()) flush(row);
    }
    ++data_row;
    return true;
  });
  flush(row);
  if (data_row != rows)
    throw ParseError(path, 0, "",
                     "the file shrank while being read (" + std::to_string(rows) +
                         " rows when counted, " + std::to_string(data_row) + " when parsed)");
  if (row != rows) values.conservativeResize(row, Eigen::NoChange);
  return values;
}

RawTable readRawTable(const std::string& path) {
  RawTable table = readRawHeader(path);
  std::vector<int> all(table.names.size());
  for (std::size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  table.values = readRawColumns(table, all);
  return table;
}

int rawRowLine(const RawTable& header, Eigen::Index row) {
  int found = 0;
  Eigen::Index seen = 0;
  forEachLine(header.file, [&](const char* begin, const char* end, int line) {
    if (line < header.first_data_line || !isDataLine(begin, end)) return true;
    if (seen++ == row) found = line;
    return found == 0;
  });
  return found;
}

int valueFileLine(const std::string& path, Eigen::Index index) {
  int found = 0;
  Eigen::Index seen = 0;
  forEachLine(path, [&](const char* begin, const char* end, int line) {
    forEachField(begin, end, ' ', [&](const char*, const char*, int) {
      if (seen++ == index && found == 0) found = line;
    });
    return found == 0;
  });
  return found;
}

Eigen::MatrixXd readValueFile(const std::string& path, int width, long double* time_origin) {
  std::vector<double> values;
  RelativeStamps stamps{time_origin};
  forEachLine(path, [&](const char* begin, const char* end, int line) {
    forEachField(begin, end, ' ', [&](const char* b, const char* e, int) {
      double x = 0.0;
      if (!stamps.read(b, e, &x) || !std::isfinite(x))
        throw ParseError(path, line, "", "'" + std::string(b, e) + "' is not a finite number");
      values.push_back(x);
    });
    return true;
  });
  if (values.empty()) throw ParseError(path, 0, "", "has no values");
  if (values.size() % static_cast<std::size_t>(width) != 0)
    throw ParseError(path, 0, "",
                     "has " + std::to_string(values.size()) + " values, not a multiple of " +
                         std::to_string(width) + " (one per joint per sample)");
  const auto rows = static_cast<Eigen::Index>(values.size() / static_cast<std::size_t>(width));
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), rows, width);
}

namespace {

/// The runs of digits in a column name, without leading zeros ("q_joint012" -> {"12"}).
std::vector<std::string> numbersIn(const std::string& name) {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < name.size();) {
    if (!std::isdigit(static_cast<unsigned char>(name[k]))) {
      ++k;
      continue;
    }
    std::size_t end = k;
    while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
    std::size_t first = k;
    while (first + 1 < end && name[first] == '0') ++first;
    out.push_back(name.substr(first, end - first));
    k = end;
  }
  return out;
}

std::string joined(const RawTable& table, const std::vector<int>& columns) {
  std::string list;
  for (int c : columns) list += (list.empty() ? "" : ", ") + table.names[c];
  return list;
}

/// Whether the names differ in exactly one place, a letter in each ("q_a", "q_b"; "fx", "fy"):
/// an order by that letter.
bool oneLetterApart(const RawTable& table, const std::vector<int>& matched) {
  const std::string& first = table.names[static_cast<std::size_t>(matched[0])];
  std::size_t at = std::string::npos;
  for (int c : matched) {
    const std::string& name = table.names[static_cast<std::size_t>(c)];
    if (name.size() != first.size()) return false;
    for (std::size_t k = 0; k < name.size(); ++k)
      if (name[k] != first[k]) {
        if (at != std::string::npos && at != k) return false;
        at = k;
      }
  }
  if (at == std::string::npos) return false;
  for (int c : matched)
    if (!std::isalpha(static_cast<unsigned char>(table.names[static_cast<std::size_t>(c)][at])))
      return false;
  return true;
}

/// A glob's matches in joint order: by the numbers in their names (natural order, "q2" before
/// "q10", "q_joint1" before "q_joint2" whatever the file's order), or by the one letter in which
/// they differ ("q_a" before "q_b"). Other matches ("q_shoulder", "q_elbow"), or names with the
/// same numbers, cannot be ordered: a ParseError asking for the list.
void naturalOrder(const RawTable& table, const std::string& entry, const std::string& what,
                  std::vector<int>& matched) {
  if (matched.size() < 2) return;
  if (oneLetterApart(table, matched)) {
    std::stable_sort(matched.begin(), matched.end(), [&](int a, int b) {
      return table.names[static_cast<std::size_t>(a)] < table.names[static_cast<std::size_t>(b)];
    });
    return;
  }
  std::vector<std::vector<std::string>> numbers;
  for (int c : matched) {
    numbers.push_back(numbersIn(table.names[c]));
    const bool repeated =
        std::find(numbers.begin(), numbers.end() - 1, numbers.back()) != numbers.end() - 1;
    if (numbers.back().empty() || repeated)
      throw ParseError(table.file, 0, what,
                       "'" + entry + "' matches " + joined(table, matched) +
                           ", whose joint order cannot be told from the names (" +
                           (repeated ? "two hold the same numbers"
                                     : "'" + table.names[c] +
                                           "' holds no joint "
                                           "number") +
                           "): list the columns in joint order, separated by commas");
  }
  std::stable_sort(matched.begin(), matched.end(),
                   [&](int a, int b) { return naturalLess(table.names[a], table.names[b]); });
}

}  // namespace

std::vector<int> selectColumns(const RawTable& table, const std::string& selector, int expected,
                               const std::string& what) {
  std::vector<int> out;
  for (const std::string_view field : splitFields(selector, ',')) {
    const std::string entry = trim(std::string(field));
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
      naturalOrder(table, entry, what, matched);
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
