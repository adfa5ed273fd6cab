#include "data/dataset_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string_view>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"
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

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}
/// The common row, parsed in one pass: 1 + 4n plain numbers (what std::from_chars reads, finite)
/// separated by single commas, trailing blanks allowed at the end. Writes time and column k of
/// q, dq, ddq and tau; false for anything else (a '+', blanks around a field, out of range, not
/// finite, another field count), which the checked parse then names.
bool parsePlainRow(std::string_view line, int n, Trajectory& chunk, int k) {
  const char* p = line.data();
  const char* const end = p + line.size();
  // One field into x; p then points past its comma (false when the comma is not there).
  const auto field = [&](double& x) {
    const auto parsed = std::from_chars(p, end, x);
    if (parsed.ec != std::errc() || !std::isfinite(x) || parsed.ptr == end || *parsed.ptr != ',')
      return false;
    p = parsed.ptr + 1;
    return true;
  };
  if (!field(chunk.time[k])) return false;
  Eigen::MatrixXd* const blocks[] = {&chunk.q, &chunk.dq, &chunk.ddq, &chunk.tau};
  for (int b = 0; b < 4; ++b) {
    double* column = blocks[b]->col(k).data();
    for (int j = 0; j < n; ++j) {
      if (b < 3 || j + 1 < n) {
        if (!field(column[j])) return false;
        continue;
      }
      const auto parsed = std::from_chars(p, end, column[j]);
      return parsed.ec == std::errc() && std::isfinite(column[j]) &&
             trim(std::string_view(parsed.ptr, static_cast<std::size_t>(end - parsed.ptr))).empty();
    }
  }
  return false;  // not reached: n >= 1
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

void writeDatasetCsv(const std::string& path, const Trajectory& trajectory, ThreadPool* pool) {
  AtomicWriter out(path);
  writeDatasetCsv(out, trajectory, pool);
  out.commit();
}

namespace {
/// The most characters std::to_chars' shortest form of a double takes ("-2.2250738585072014e-308":
/// 24), with room to spare.
constexpr std::size_t kNumberChars = 32;
/// A block's text buffer [bytes]: the rows a thread formats at a time.
constexpr std::size_t kBlockBytes = std::size_t{1} << 19;
/// Blocks formatted per round at most: with the round being written, 2 x 16 x 512 kB in memory.
constexpr int kMaxBlocksPerRound = 16;

/// Rows [first, last) of the dataset as CSV text into `text`, whose size is at least
/// (last - first) * (1 + 4 n) * kNumberChars (never reallocated: no allocation, nothing thrown).
/// Returns the length written.
std::size_t formatRows(const Trajectory& t, int first, int last, std::vector<char>& text) {
  const int n = t.numJoints();
  char* at = text.data();
  const auto append = [&](double x, char separator) {
    at = std::to_chars(at, at + kNumberChars - 1, x).ptr;
    *at++ = separator;
  };
  for (int k = first; k < last; ++k) {
    append(t.time[k], ',');
    for (const Eigen::MatrixXd* m : {&t.q, &t.dq, &t.ddq, &t.tau})
      for (int i = 0; i < n; ++i) append((*m)(i, k), ',');
    at[-1] = '\n';  // the row's last separator
  }
  return static_cast<std::size_t>(at - text.data());
}
}  // namespace

namespace {
/// Formats rows [first, last) into `text` (sized for them) in buffer `slot` (0 to
/// 2 kMaxBlocksPerRound - 1: the same slot is never in use on two threads at once) and returns the
/// length written.
using FormatBlock =
    std::function<std::size_t(int first, int last, int slot, std::vector<char>& text)>;

void writeBlocks(AtomicWriter& out, int n, int samples, const FormatBlock& format,
                 ThreadPool* pool) {
  out.write(datasetHeader(n) + "\n");
  // Streamed a few blocks of rows at a time: memory independent of the length. Formatting
  // (std::to_chars) and writing take most of the time; in each round, one task writes the last
  // round's blocks in order while the others format this round's, each into its own buffer (two
  // sets of buffers, used in turn). Without a pool, the same tasks one after another: the same
  // bytes.
  const std::size_t row_bytes = static_cast<std::size_t>(1 + 4 * n) * kNumberChars;
  const int rows_per_block = std::min(
      std::max(samples, 1), static_cast<int>(std::max<std::size_t>(16, kBlockBytes / row_bytes)));
  const int blocks = (samples + rows_per_block - 1) / rows_per_block;
  const int threads = pool ? pool->numThreads() : 1;
  const int per_round = std::min({blocks, 2 * threads, kMaxBlocksPerRound});
  std::vector<char> texts[2][kMaxBlocksPerRound];
  std::size_t lengths[2][kMaxBlocksPerRound] = {};
  for (auto& set : texts)
    for (int slot = 0; slot < per_round; ++slot)
      set[slot].resize(static_cast<std::size_t>(rows_per_block) * row_bytes);
  std::exception_ptr failure;
  std::vector<std::exception_ptr> failures(static_cast<std::size_t>(per_round));
  int pending = 0;  // blocks formatted in the last round, not yet written (in set `1 - set`)
  for (int first = 0, set = 0; first < blocks || pending > 0; set = 1 - set) {
    const int round = std::min(per_round, blocks - first);
    const auto task = [&](int index) {
      if (index == 0) {
        try {
          for (int slot = 0; slot < pending; ++slot)
            out.write({texts[1 - set][slot].data(), lengths[1 - set][slot]});
        } catch (...) {
          failure = std::current_exception();  // rethrown on this thread, after the round
        }
        return;
      }
      const int block = first + index - 1;
      try {
        lengths[set][index - 1] =
            format(block * rows_per_block, std::min(samples, (block + 1) * rows_per_block),
                   set * kMaxBlocksPerRound + index - 1, texts[set][index - 1]);
      } catch (...) {
        failures[static_cast<std::size_t>(index - 1)] = std::current_exception();  // likewise
      }
    };
    if (pool && round > 0)
      pool->parallelFor(round + 1, [&](int index, int) { task(index); });
    else
      for (int index = 0; index <= round; ++index) task(index);
    if (failure) std::rethrow_exception(failure);
    for (const std::exception_ptr& f : failures)
      if (f) std::rethrow_exception(f);
    pending = round;
    first += round;
  }
}
}  // namespace

void writeDatasetCsv(AtomicWriter& out, const Trajectory& trajectory, ThreadPool* pool) {
  const int n = trajectory.numJoints(), samples = trajectory.numSamples();
  for (const Eigen::MatrixXd* m : {&trajectory.q, &trajectory.dq, &trajectory.ddq, &trajectory.tau})
    if (m->rows() != n || m->cols() != samples)
      throw InputError("trajectory matrices must all be " + std::to_string(n) + " x " +
                       std::to_string(samples));
  writeBlocks(
      out, n, samples,
      [&](int first, int last, int, std::vector<char>& text) {
        return formatRows(trajectory, first, last, text);
      },
      pool);
}

void writeDatasetCsv(AtomicWriter& out, int num_joints, int samples, const DatasetRows& rows,
                     ThreadPool* pool) {
  std::vector<Trajectory> chunks(2 * kMaxBlocksPerRound);
  writeBlocks(
      out, num_joints, samples,
      [&](int first, int last, int slot, std::vector<char>& text) {
        Trajectory& chunk = chunks[static_cast<std::size_t>(slot)];
        rows(first, last, chunk);
        if (chunk.numJoints() != num_joints || chunk.numSamples() != last - first)
          throw InputError("a dataset's rows came back in the wrong shape");
        return formatRows(chunk, 0, last - first, text);
      },
      pool);
}

void writeExternalTorqueCsv(const std::string& path, const Eigen::VectorXd& time,
                            const Eigen::MatrixXd& external) {
  if (external.cols() != time.size())
    throw InputError("the external torques have " + std::to_string(external.cols()) +
                     " samples, the time " + std::to_string(time.size()));
  AtomicWriter out(path);
  std::string row = "t";
  for (Eigen::Index j = 1; j <= external.rows(); ++j) row += ",tau_ext" + std::to_string(j);
  out.write(row + "\n");
  std::array<char, 32> number;
  const auto append = [&](double x) {
    const auto end = std::to_chars(number.data(), number.data() + number.size(), x).ptr;
    row.append(number.data(), end);
  };
  for (Eigen::Index k = 0; k < time.size(); ++k) {
    row.clear();
    append(time[k]);
    for (Eigen::Index j = 0; j < external.rows(); ++j) {
      row += ',';
      append(external(j, k));
    }
    row += '\n';
    out.write(row);
  }
  out.commit();
}

DatasetReader::DatasetReader(const std::string& path, int expected_joints)
    : path_(path), lines_(std::make_unique<LineReader>(path)) {
  std::string_view line;
  bool empty = !lines_->next(line);
  if (!empty && trim(line).empty()) {  // a blank first line: an empty file, or a missing header
    std::string_view rest;
    empty = true;
    while (empty && lines_->next(rest)) empty = trim(rest).empty();
    if (!empty) line = {};  // the blank line is the header: refused below
  }
  if (empty)
    throw ParseError(path, 1, "",
                     "empty file: expected the header " +
                         datasetHeader(expected_joints > 0 ? expected_joints : 1));
  const int header_line = 1;
  // Header: t, then 4 blocks of n names.
  std::vector<std::string_view> header = splitFields(line);
  for (auto& h : header) h = trim(h);
  if ((header.size() - 1) % 4 != 0 || header.size() < 5)
    throw ParseError(path, header_line, "",
                     "header has " + std::to_string(header.size()) +
                         " columns; expected t,q1..qn,dq1..dqn,ddq1..ddqn,tau1..taun "
                         "(1 + 4n columns)");
  n_ = static_cast<int>((header.size() - 1) / 4);
  if (expected_joints >= 0 && n_ != expected_joints)
    throw ParseError(path, header_line, "",
                     "header describes " + std::to_string(n_) + " joints, the model has " +
                         std::to_string(expected_joints));
  const std::vector<std::string> names = columnNames(n_);
  for (std::size_t c = 0; c < names.size(); ++c)
    if (header[c] != names[c])
      throw ParseError(path, header_line, "column " + std::to_string(c + 1),
                       "expected '" + names[c] + "', found '" + std::string(header[c]) + "'");
}

DatasetReader::~DatasetReader() = default;

void DatasetReader::parseRow(std::string_view line, int line_number, Trajectory& chunk, int k) {
  if (parsePlainRow(line, n_, chunk, k)) return;
  // Checked, field by field: accepts what the plain parse does not ('+', blanks around a field,
  // underflow) and names the first field at fault.
  const std::size_t columns = 1 + 4 * static_cast<std::size_t>(n_);
  // Fields parsed in place (std::from_chars: no copy, no locale, no allocation per cell).
  std::size_t start = 0;
  for (std::size_t c = 0; c < columns; ++c) {
    const std::size_t comma = line.find(',', start);
    const bool last = c + 1 == columns;
    if ((comma == std::string_view::npos) != last) {
      const auto fields = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
      throw ParseError(path_, line_number, "",
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
    const auto column = [&] { return c == 0 ? std::string("t") : columnNames(n_)[c]; };
    if (digits.empty() || signed_twice || parsed.ptr != digits.data() + digits.size() ||
        (parsed.ec != std::errc() && parsed.ec != std::errc::result_out_of_range))
      throw ParseError(path_, line_number, column(),
                       "'" + std::string(field) + "' is not a number");
    if (parsed.ec == std::errc::result_out_of_range)  // overflow (inf) or underflow (0, subnormal)
      x = std::strtod(std::string(digits).c_str(), nullptr);
    if (!std::isfinite(x))
      throw ParseError(path_, line_number, column(), "'" + std::string(field) + "' is not finite");
    if (c == 0) {  // its order is checked by read(), row after row
      chunk.time[k] = x;
      continue;
    }
    const int block = static_cast<int>((c - 1) / n_), joint = static_cast<int>((c - 1) % n_);
    Eigen::MatrixXd* target[] = {&chunk.q, &chunk.dq, &chunk.ddq, &chunk.tau};
    (*target[block])(joint, k) = x;
  }
}

int DatasetReader::read(Trajectory& chunk, int max_samples, ThreadPool* pool) {
  if (max_samples < 1) throw InputError("DatasetReader::read: max_samples must be >= 1");
  if (chunk.numJoints() != n_ || chunk.numSamples() != max_samples) chunk.resize(n_, max_samples);
  // The chunk's rows copied (the line reader's buffer moves), then parsed in blocks on the pool's
  // threads; errors are thrown in the order of the file: the first row at fault, whatever found
  // it first.
  text_.clear();
  offsets_.clear();
  line_numbers_.clear();
  std::exception_ptr pending;  // a blank line before a row, or too many rows: after the rows
  int k = 0;
  std::string_view line;
  while (!done_ && k < max_samples) {
    if (!lines_->next(line)) {
      done_ = true;
      break;
    }
    // Blank lines at the end of the file are ignored; elsewhere they are errors.
    if (trim(line).empty()) {
      if (blank_line_ == 0) blank_line_ = lines_->lineNumber();
      continue;
    }
    if (blank_line_ != 0) {
      pending = std::make_exception_ptr(
          ParseError(path_, blank_line_, "",
                     "row has 1 fields, the header has " + std::to_string(1 + 4 * n_)));
      break;
    }
    if (samples_ + k >= std::numeric_limits<int>::max()) {
      pending = std::make_exception_ptr(
          ParseError(path_, lines_->lineNumber(), "", "more than 2^31 - 1 rows"));
      break;
    }
    offsets_.push_back(text_.size());
    text_.append(line);
    line_numbers_.push_back(lines_->lineNumber());
    ++k;
  }
  offsets_.push_back(text_.size());
  constexpr int kBlock = 256;
  const int blocks = (k + kBlock - 1) / kBlock;
  std::vector<std::pair<int, std::exception_ptr>> errors(static_cast<std::size_t>(blocks),
                                                         {k, nullptr});
  const auto parse = [&](int block, int) {
    for (int r = block * kBlock; r < std::min(k, (block + 1) * kBlock); ++r) {
      try {
        const auto at = static_cast<std::size_t>(r);
        parseRow(std::string_view(text_).substr(offsets_[at], offsets_[at + 1] - offsets_[at]),
                 line_numbers_[at], chunk, r);
      } catch (...) {
        errors[static_cast<std::size_t>(block)] = {r, std::current_exception()};
        return;
      }
    }
  };
  if (pool && blocks > 1)
    pool->parallelFor(blocks, parse);
  else
    for (int b = 0; b < blocks; ++b) parse(b, 0);
  int bad_row = k;  // the first row that failed to parse
  std::exception_ptr parse_error;
  for (const auto& [row, error] : errors)
    if (error) {
      bad_row = row;
      parse_error = error;
      break;
    }
  for (int r = 0; r < bad_row; ++r) {
    const double t = chunk.time[r];
    if (samples_ + r > 0 && !(t > last_time_))
      throw ParseError(path_, line_numbers_[static_cast<std::size_t>(r)], "t",
                       "time must increase strictly (" + formatNumber(t) + " after " +
                           formatNumber(last_time_) + ")");
    last_time_ = t;
  }
  if (parse_error) std::rethrow_exception(parse_error);
  if (pending) std::rethrow_exception(pending);
  if (done_ && samples_ + k == 0) throw ParseError(path_, 1, "", "no data rows after the header");
  samples_ += k;
  if (k < max_samples) chunk.truncate(k);
  return k;
}

Trajectory readDatasetCsv(const std::string& path, int expected_joints) {
  DatasetReader reader(path, expected_joints);
  const int n = reader.numJoints();
  // Chunks of growing size, appended: the memory check before each growth names the file.
  std::vector<Trajectory> chunks;
  long long samples = 0;
  int size = 1024;
  while (true) {
    requireMemory(2.0 * static_cast<double>(samples + size) * (1 + 4 * n) * sizeof(double),
                  path + ": " + std::to_string(samples + size) + " samples of " +
                      std::to_string(n) + " joints");
    Trajectory chunk;
    const int got = reader.read(chunk, size);
    if (got == 0) break;
    samples += got;
    chunks.push_back(std::move(chunk));
    size = static_cast<int>(std::min<long long>(2LL * size, 1 << 20));
  }
  Trajectory out;
  out.resize(n, static_cast<int>(samples));
  Eigen::Index at = 0;
  for (Trajectory& c : chunks) {
    const Eigen::Index m = c.numSamples();
    out.time.segment(at, m) = c.time;
    out.q.middleCols(at, m) = c.q;
    out.dq.middleCols(at, m) = c.dq;
    out.ddq.middleCols(at, m) = c.ddq;
    out.tau.middleCols(at, m) = c.tau;
    at += m;
    c = Trajectory();
  }
  return out;
}

}  // namespace dynid
