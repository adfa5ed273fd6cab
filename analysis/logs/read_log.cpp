#include "analysis/logs/read_log.hpp"

#include <algorithm>
#include <utility>

#include "analysis/logs/bag_log.hpp"
#include "analysis/logs/raw_log.hpp"
#include "core/errors.hpp"
#include "data/bags/bag.hpp"

namespace dynid {

Eigen::VectorXd RawSignals::column(int c, Eigen::Index first, Eigen::Index count) const {
  if (count < 0) count = rows - first;
  if (!spilled || c == 0) return values.col(c).segment(first, count);
  Eigen::VectorXd out(count);
  spilled->read(c - 1, first, out.data(), count);
  return out;
}

void RawSignals::setColumn(int c, const Eigen::VectorXd& x) {
  if (!spilled || c == 0)
    values.col(c).head(rows) = x;
  else
    spilled->write(c - 1, 0, x.data(), rows);
}

void RawSignals::keep(const std::vector<Eigen::Index>& kept) {
  const auto count = static_cast<Eigen::Index>(kept.size());
  bool same = count == rows;
  for (Eigen::Index k = 0; k < count && same; ++k) same = kept[static_cast<std::size_t>(k)] == k;
  if (same) return;
  for (int c = 0; c < numColumns(); ++c) {
    const Eigen::VectorXd x = column(c);
    Eigen::VectorXd y(count);
    for (Eigen::Index k = 0; k < count; ++k) y[k] = x[kept[static_cast<std::size_t>(k)]];
    if (!spilled || c == 0)
      values.col(c).head(count) = y;
    else
      spilled->write(c - 1, 0, y.data(), count);
  }
  rows = count;
}

namespace {

/// A one-file-per-signal log (time, q, tau or currents, and dq, ddq when given) into `out`.
void readSignalFiles(const LogSource& source, int n, RawSignals& out) {
  if (n <= 0) throw InputError("give the number of joints (`joints`) for one-file-per-signal logs");
  if (source.time_file.empty() || source.q_file.empty() || source.tau_file.empty())
    throw InputError("one-file-per-signal logs need the time, q and tau (or current) files");
  const Eigen::VectorXd time = readValueFile(source.time_file, 1, &out.time_origin).col(0);
  out.line_of = [file = source.time_file](Eigen::Index k) { return valueFileLine(file, k); };
  const Eigen::Index samples = time.size();
  out.has_dq = !source.dq_file.empty();
  out.has_ddq = !source.ddq_file.empty();
  out.values.resize(samples, 1 + (2 + (out.has_dq ? 1 : 0) + (out.has_ddq ? 1 : 0)) * n);
  out.values.col(0) = time;
  int at = 1;
  for (const auto& [name, file] : {std::pair<const char*, const std::string*>{"q", &source.q_file},
                                   {source.current ? "current" : "tau", &source.tau_file},
                                   {"dq", &source.dq_file},
                                   {"ddq", &source.ddq_file}}) {
    if (file->empty()) continue;
    const Eigen::MatrixXd m = readValueFile(*file, n);
    if (m.rows() != samples)
      throw ParseError(
          *file, 0, name,
          "has " + std::to_string(m.rows()) + " samples, the time file " + std::to_string(samples));
    out.values.middleCols(at, n) = m;
    at += n;
  }
}

}  // namespace

RawSignals readLog(const LogSource& source, const std::string& table_path,
                   const std::string& scratch_dir) {
  if (table_path.empty() && source.arrays != nullptr) return *source.arrays;
  if (!table_path.empty() && bags::isBag(table_path))
    return readBagLog(source, table_path, scratch_dir);
  RawSignals out;
  int n = source.num_joints;
  std::string tau_file = table_path;
  if (!table_path.empty()) {
    const RawTable header = readRawHeader(table_path, source.decimal_comma);
    const std::vector<int> q =
        selectColumns(header, source.q_columns, n > 0 ? n : -1, "`q_columns`");
    n = static_cast<int>(q.size());
    std::vector<int> columns = selectColumns(header, source.time_column, 1, "`time_column`");
    columns.insert(columns.end(), q.begin(), q.end());
    const std::vector<int> tau = selectColumns(header, source.tau_columns, n,
                                               source.current ? "`current`" : "`tau_columns`");
    columns.insert(columns.end(), tau.begin(), tau.end());
    for (const auto& [selector, what] : {std::pair{&source.dq_columns, "`dq_columns`"},
                                         std::pair{&source.ddq_columns, "`ddq_columns`"}})
      if (!selector->empty()) {
        const std::vector<int> more = selectColumns(header, *selector, n, what);
        columns.insert(columns.end(), more.begin(), more.end());
      }
    std::vector<Eigen::Index> skipped;
    std::vector<int> skipped_lines;
    if (!scratch_dir.empty())
      out.spilled =
          std::make_shared<ScratchColumns>(scratch_dir, static_cast<int>(columns.size()) - 1);
    out.values =
        readRawColumns(header, columns, &out.time_origin, source.skip_missing ? &skipped : nullptr,
                       &skipped_lines, out.spilled.get());
    const auto names = [&](const std::vector<int>& selected) {
      std::vector<std::string> list;
      for (int c : selected) list.push_back(header.names[static_cast<std::size_t>(c)]);
      return list;
    };
    out.columns.time = header.names[static_cast<std::size_t>(columns[0])];
    out.columns.q = names(q);
    out.columns.tau = names(tau);
    std::size_t at = 1 + 2 * q.size();
    for (auto* role : {&out.columns.dq, &out.columns.ddq})
      if (role == &out.columns.dq ? !source.dq_columns.empty() : !source.ddq_columns.empty()) {
        *role = names({columns.begin() + static_cast<std::ptrdiff_t>(at),
                       columns.begin() + static_cast<std::ptrdiff_t>(at + q.size())});
        at += q.size();
      }
    if (skipped.empty()) {
      out.line_of = [header](Eigen::Index row) { return rawRowLine(header, row); };
    } else {
      // A kept row's data row in the file: past every skipped one at or before it.
      out.line_of = [header, skipped](Eigen::Index row) {
        for (const Eigen::Index s : skipped)
          if (s <= row) ++row;
        return rawRowLine(header, row);
      };
      out.skipped_missing = static_cast<long>(skipped.size());
      std::string lines;
      for (std::size_t k = 0; k < std::min<std::size_t>(skipped.size(), 5); ++k)
        lines += (k == 0 ? "" : ", ") + std::to_string(skipped_lines[k]);
      out.warnings.push_back(
          std::to_string(skipped.size()) + " row(s) with a missing value (empty, nan or inf) " +
          "left out (`skip_missing`), at line(s) " + lines + (skipped.size() > 5 ? ", ..." : "") +
          ": the resampling bridges them, and a run splits where they leave a gap longer than the "
          "gap limit");
    }
    out.has_dq = !source.dq_columns.empty();
    out.has_ddq = !source.ddq_columns.empty();
  } else {
    readSignalFiles(source, n, out);
    tau_file = source.tau_file;
  }
  out.tau_file = tau_file;
  out.n = n;
  out.rows = out.values.rows();
  out.file = table_path.empty() ? source.time_file : table_path;
  out.ddq_at = 1 + (out.has_dq ? 3 : 2) * n;
  return out;
}

}  // namespace dynid
