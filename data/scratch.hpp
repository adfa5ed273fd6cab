// Scratch storage on disk for what a long log makes too large to hold: columns of doubles in an
// anonymous temporary file (never a name another process can reach or a link can redirect),
// removed by the system when it is closed, whatever ends the process.
#pragma once

#include <cstdint>
#include <string>

namespace dynid {

/// `columns` columns of doubles in a temporary file in `dir`: created with O_TMPFILE (no name at
/// all), else exclusively under a random name that is unlinked at once. The columns grow as rows
/// are written past their end (stored in blocks of kBlockRows rows, every column's block side by
/// side), so a reader that does not know the count in advance appends. Nothing is cached: every
/// write and read goes to the file (the system's page cache keeps what memory allows). write and
/// read may be called from several threads at once for different ranges. Throws Error naming
/// `dir` when the file cannot be made, and naming it and the reason (a full disk) when a write or
/// read fails.
class ScratchColumns {
 public:
  static constexpr std::int64_t kBlockRows = 1 << 16;
  ScratchColumns(const std::string& dir, int columns, std::int64_t rows = 0);
  ~ScratchColumns();
  ScratchColumns(const ScratchColumns&) = delete;
  ScratchColumns& operator=(const ScratchColumns&) = delete;

  /// values[0, count) into rows [first, first + count) of `column`; rows past the end are added
  /// (the rows in between, and every other column's new rows, read as zeros until written). Not
  /// concurrent with a call that adds rows.
  void write(int column, std::int64_t first, const double* values, std::int64_t count);
  /// Rows [first, first + count) of `column` into values[0, count).
  void read(int column, std::int64_t first, double* values, std::int64_t count) const;

  int columns() const { return columns_; }
  std::int64_t rows() const { return rows_; }
  const std::string& dir() const { return dir_; }

 private:
  /// Calls io(file offset, index into the caller's values, count) for each block's part of rows
  /// [first, first + count) of `column`.
  template <typename Io>
  void eachBlock(int column, std::int64_t first, std::int64_t count, Io io) const;
  std::string dir_;
  int columns_ = 0;
  std::int64_t rows_ = 0;
  int fd_ = -1;
};

/// The nearest existing directory at or above `path` (a directory that a command's output
/// directory will be made in): where its scratch file goes, on the output's file system. "." for
/// a relative path none of whose ancestors exist.
std::string nearestExistingDirectory(const std::string& path);

}  // namespace dynid
