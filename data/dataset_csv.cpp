#include "data/dataset_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <vector>

#include "core/errors.hpp"
#include "core/memory.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {
std::vector<std::string> columnNames(int n) {
  std::vector<std::string> names{"t"};
  for (const char* prefix : {"q", "dq", "ddq", "tau"})
    for (int i = 1; i <= n; ++i) names.push_back(prefix + std::to_string(i));
  return names;
}

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}
}  // namespace

std::string datasetHeader(int num_joints) {
  std::string header;
  for (const std::string& name : columnNames(num_joints)) {
    if (!header.empty()) header += ',';
    header += name;
  }
  return header;
}

void writeDatasetCsv(const std::string& path, const Trajectory& trajectory) {
  const int n = trajectory.numJoints(), samples = trajectory.numSamples();
  for (const Eigen::MatrixXd* m : {&trajectory.q, &trajectory.dq, &trajectory.ddq, &trajectory.tau})
    if (m->rows() != n || m->cols() != samples)
      throw InputError("trajectory matrices must all be " + std::to_string(n) + " x " +
                       std::to_string(samples));
  // Streamed: one row at a time through the writer's buffer, memory independent of the length.
  AtomicWriter out(path);
  out.write(datasetHeader(n) + "\n");
  std::string row;
  std::array<char, 32> number;
  const auto append = [&](double x) {
    const auto end = std::to_chars(number.data(), number.data() + number.size(), x).ptr;
    row.append(number.data(), end);
  };
  for (int k = 0; k < samples; ++k) {
    row.clear();
    append(trajectory.time[k]);
    for (const Eigen::MatrixXd* m :
         {&trajectory.q, &trajectory.dq, &trajectory.ddq, &trajectory.tau})
      for (int i = 0; i < n; ++i) {
        row += ',';
        append((*m)(i, k));
      }
    row += '\n';
    out.write(row);
  }
  out.commit();
}

Trajectory readDatasetCsv(const std::string& path, int expected_joints) {
  const std::string text = readFile(path, std::numeric_limits<double>::infinity());
  std::vector<std::string_view> lines;
  // A UTF-8 byte-order mark (spreadsheets write one) is not part of the header.
  const std::size_t first = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  for (std::size_t start = first; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    lines.push_back(std::string_view(text).substr(start, end - start));
    start = end + 1;
  }
  // Blank lines at the end of the file are ignored; elsewhere they are errors.
  while (!lines.empty() && trim(lines.back()).empty()) lines.pop_back();
  if (lines.empty())
    throw ParseError(path, 1, "",
                     "empty file: expected the header " +
                         datasetHeader(expected_joints > 0 ? expected_joints : 1));

  // Header: t, then 4 blocks of n names.
  std::vector<std::string_view> header = splitFields(lines[0]);
  for (auto& h : header) h = trim(h);
  if ((header.size() - 1) % 4 != 0 || header.size() < 5)
    throw ParseError(path, 1, "",
                     "header has " + std::to_string(header.size()) +
                         " columns; expected t,q1..qn,dq1..dqn,ddq1..ddqn,tau1..taun "
                         "(1 + 4n columns)");
  const int n = static_cast<int>((header.size() - 1) / 4);
  if (expected_joints >= 0 && n != expected_joints)
    throw ParseError(path, 1, "",
                     "header describes " + std::to_string(n) + " joints, the model has " +
                         std::to_string(expected_joints));
  const std::vector<std::string> names = columnNames(n);
  for (std::size_t c = 0; c < names.size(); ++c)
    if (header[c] != names[c])
      throw ParseError(path, 1, "column " + std::to_string(c + 1),
                       "expected '" + names[c] + "', found '" + std::string(header[c]) + "'");

  if (lines.size() - 1 > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw ParseError(path, 0, "", "more than 2^31 - 1 rows");
  const int samples = static_cast<int>(lines.size()) - 1;
  if (samples < 1) throw ParseError(path, 1, "", "no data rows after the header");
  requireMemory(
      static_cast<double>(samples) * (1 + 4 * n) * sizeof(double),
      path + ": " + std::to_string(samples) + " samples of " + std::to_string(n) + " joints");
  Trajectory out;
  out.resize(n, samples);
  const std::size_t columns = names.size();
  for (int k = 0; k < samples; ++k) {
    const int line_number = k + 2;
    const std::string_view line = lines[k + 1];
    // Fields parsed in place (std::from_chars: no copy, no locale, no allocation per cell).
    std::size_t start = 0;
    for (std::size_t c = 0; c < columns; ++c) {
      const std::size_t comma = line.find(',', start);
      const bool last = c + 1 == columns;
      if ((comma == std::string_view::npos) != last) {
        const auto fields = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
        throw ParseError(path, line_number, "",
                         "row has " + std::to_string(fields) + " fields, the header has " +
                             std::to_string(columns));
      }
      const std::string_view field =
          trim(line.substr(start, last ? std::string_view::npos : comma - start));
      start = comma + 1;
      std::string_view digits = field;
      bool signed_twice = false;
      if (!digits.empty() && digits.front() == '+') {  // accepted, as strtod does
        digits.remove_prefix(1);
        signed_twice = !digits.empty() && digits.front() == '-';
      }
      double x = 0.0;
      const auto parsed = std::from_chars(digits.data(), digits.data() + digits.size(), x);
      if (digits.empty() || signed_twice || parsed.ptr != digits.data() + digits.size() ||
          (parsed.ec != std::errc() && parsed.ec != std::errc::result_out_of_range))
        throw ParseError(path, line_number, names[c],
                         "'" + std::string(field) + "' is not a number");
      if (parsed.ec ==
          std::errc::result_out_of_range)  // overflow (inf) or underflow (0, subnormal)
        x = std::strtod(std::string(digits).c_str(), nullptr);
      if (!std::isfinite(x))
        throw ParseError(path, line_number, names[c], "'" + std::string(field) + "' is not finite");
      if (c == 0) {
        out.time[k] = x;
        if (k > 0 && !(x > out.time[k - 1]))
          throw ParseError(path, line_number, "t",
                           "time must increase strictly (" + std::string(field) + " after " +
                               formatDouble(out.time[k - 1]) + ")");
        continue;
      }
      const int block = static_cast<int>((c - 1) / n), joint = static_cast<int>((c - 1) % n);
      Eigen::MatrixXd* target[] = {&out.q, &out.dq, &out.ddq, &out.tau};
      (*target[block])(joint, k) = x;
    }
  }
  return out;
}

}  // namespace dynid
