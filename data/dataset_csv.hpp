// Trajectory datasets as CSV: header t,q1..qn,dq1..dqn,ddq1..ddqn,tau1..taun, one sample per row,
// SI units (s, rad, rad/s, rad/s^2, N m), comma-separated, '.' as the decimal point.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/parallel.hpp"
#include "core/trajectory.hpp"

namespace dynid {

class AtomicWriter;

/// The header line (without newline) for n joints.
std::string datasetHeader(int num_joints);

/// Writes the trajectory atomically (io.hpp), numbers in shortest round-trip form, so reading the
/// file back gives exactly the same doubles. Throws Error when the file cannot be written,
/// InputError when the trajectory's matrices disagree in size.
void writeDatasetCsv(const std::string& path, const Trajectory& trajectory,
                     ThreadPool* pool = nullptr);
/// The same rows into `out` (a member of an output set), which the caller commits. With a pool,
/// blocks of rows are formatted on its threads and written in order: the same bytes.
void writeDatasetCsv(AtomicWriter& out, const Trajectory& trajectory, ThreadPool* pool = nullptr);
/// Rows [first, last) of a dataset into `chunk` (sized n x (last - first) by the callee); called
/// from several threads at once for different rows and chunks.
using DatasetRows = std::function<void(int first, int last, Trajectory& chunk)>;
/// The same for a dataset of `num_joints` joints and `samples` rows held elsewhere (a scratch
/// file): read back and formatted a few blocks at a time, on the pool's threads. The same bytes as
/// the trajectory's. Throws what `rows` throws.
void writeDatasetCsv(AtomicWriter& out, int num_joints, int samples, const DatasetRows& rows,
                     ThreadPool* pool = nullptr);

/// A simulation's ground truth of external joint torques: header t,tau_ext1..tau_extn, one row per
/// sample (time.size() columns of `external`, n x samples), written atomically. Throws Error when
/// the file cannot be written, InputError when the sizes disagree.
void writeExternalTorqueCsv(const std::string& path, const Eigen::VectorXd& time,
                            const Eigen::MatrixXd& external);

class LineReader;

/// A dataset read in chunks of samples, in memory independent of its length, with the checks and
/// messages of readDatasetCsv (the header when constructed, every row as it is read, time
/// increasing across chunks).
class DatasetReader {
 public:
  /// Opens `path` and checks its header (and n == expected_joints when that is >= 0). Throws
  /// ParseError for an empty file or a wrong header, Error when the file cannot be read.
  explicit DatasetReader(const std::string& path, int expected_joints = -1);
  ~DatasetReader();
  DatasetReader(const DatasetReader&) = delete;
  DatasetReader& operator=(const DatasetReader&) = delete;

  /// Reads the next samples, at most max_samples (>= 1), into `chunk` (resized to n x count;
  /// its time, q, dq, ddq and tau) and returns count: 0 once the file is read. Throws ParseError
  /// at the first row at fault (line and column named), also when the file has no data row,
  /// Error when a regular file changed size while it was read.
  /// With a pool, the rows are parsed on its threads (the same result, the same first error).
  int read(Trajectory& chunk, int max_samples, ThreadPool* pool = nullptr);

  int numJoints() const { return n_; }
  const std::string& path() const { return path_; }
  /// Samples returned so far.
  long long samplesRead() const { return samples_; }

 private:
  void parseRow(std::string_view line, int line_number, Trajectory& chunk, int k);
  std::string path_;
  std::unique_ptr<LineReader> lines_;
  int n_ = 0;
  long long samples_ = 0;
  double last_time_ = 0.0;
  int blank_line_ = 0;  // the first blank line since the last row (an error if a row follows)
  bool done_ = false;
  std::string text_;                  // the chunk's rows, copied
  std::vector<std::size_t> offsets_;  // row r: text_[offsets_[r], offsets_[r + 1])
  std::vector<int> line_numbers_;
};

/// Reads a dataset. Checks the header (names the column that differs), that every row has
/// 1 + 4n fields, that every field is a finite number, and that time strictly increases; when
/// expected_joints >= 0, also that n matches it. Throws ParseError(file, line, column, ...) naming
/// the line and column at fault, Error when the file cannot be read, and InputError naming the file
/// when its samples would not fit in memory (core/memory.hpp). The whole trajectory is held:
/// what reads a long log sample by sample uses DatasetReader instead.
Trajectory readDatasetCsv(const std::string& path, int expected_joints = -1);

}  // namespace dynid
