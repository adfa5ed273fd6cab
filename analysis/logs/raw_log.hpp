// Raw robot logs as they come: delimited tables (comma, semicolon, tab or whitespace, with or
// without a header line) and one-signal-per-file layouts (a value per line, n values per sample,
// like Gaz et al.'s Panda log). Only reading and column selection live here; cleaning, filtering
// and differentiation are analysis/logs/prepare.hpp's.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "data/scratch.hpp"

namespace dynid {

/// A table: column names (from the header, or "1", "2", ... when there is none) and the values,
/// one row per sample.
struct RawTable {
  std::string file;
  std::vector<std::string> names;
  Eigen::MatrixXd values;      // rows x names.size() (readRawTable), empty from readRawHeader
  int first_data_line = 0;     // the file line of the first data row
  char delimiter = 0;          // ',', ';', '\t', or ' ' for runs of blanks
  bool decimal_comma = false;  // numbers written with ',' for the decimal point (readRawHeader's)
};

/// Reads a table. The delimiter is the first of ',', ';', '\t' found on the first data line, else
/// runs of blanks. The first line is a header when any of its fields is not a number. Blank lines
/// and lines starting with '#' are skipped. Throws ParseError naming the file, line and column of
/// a short or long row or a field that is not a finite number, or Error when the file cannot be
/// read.
RawTable readRawTable(const std::string& path);

/// The table's names, delimiter and first data line, without its values (reads up to the first
/// data line). With `decimal_comma`, numbers are written with ',' for the decimal point (as
/// European spreadsheets export them): the delimiter is then ';' or '\t' (else blanks), and a
/// table delimited by ',' is a ParseError.
RawTable readRawHeader(const std::string& path, bool decimal_comma = false);
/// Only the given columns of the table (indices into header.names), in that order: rows = data
/// lines. Every row's field count is checked, and the kept fields must be finite numbers (a text
/// column that is not asked for is never parsed). Streams the file twice (count, then parse):
/// memory is the result plus a 4 MB block. Errors as readRawTable's. With `time_origin`, the first
/// column is time stamps, read in 64-bit precision: the first row's is stored there and every
/// row holds its difference from it.
/// A field that is not a number but would be one with its ',' read as a decimal point is an
/// error that names --decimal-comma. With `skipped`, a data row whose kept field is missing (empty,
/// nan or inf: a logger's dropout) is left out and its 0-based data-row index appended, in order,
/// and its file line to `skipped_lines` when given; any other field that is not a number is still
/// an error.
/// With `spill` (columns.size() - 1 columns), every column but the first goes there as the rows
/// are parsed, a block at a time, and the result holds the first column alone: memory independent
/// of the table's length (without, the result is checked against the memory available).
Eigen::MatrixXd readRawColumns(const RawTable& header, const std::vector<int>& columns,
                               long double* time_origin = nullptr,
                               std::vector<Eigen::Index>* skipped = nullptr,
                               std::vector<int>* skipped_lines = nullptr,
                               ScratchColumns* spill = nullptr);

/// The file line of data row `row` (0-based, in file order) of a table, or 0 past the end: for
/// messages about a row found wrong after reading (it re-reads the file).
int rawRowLine(const RawTable& header, Eigen::Index row);
/// The file line holding value `index` (0-based) of a one-signal-per-file log, or 0 past the end.
int valueFileLine(const std::string& path, Eigen::Index index);

/// Reads a one-signal-per-file log: every whitespace-separated number in the file, in order,
/// shaped into samples of `width` values (width 1 for a time file). Throws ParseError naming the
/// line of a non-numeric or non-finite value, or when the count is not a multiple of `width`.
/// With `time_origin` (a time file), stamps relative to the first, as readRawColumns.
Eigen::MatrixXd readValueFile(const std::string& path, int width,
                              long double* time_origin = nullptr);

/// The columns of `table` a selector names, in order: a comma-separated list of column names,
/// 1-based indices, or shell globs over the names ("q*", "tau_?"). A glob's several matches are
/// taken in joint order, by the numbers in their names (natural order: q1, q2, ..., q10, whatever
/// the file's order). Throws ParseError (file, element = the selector) when an entry matches
/// nothing, when a glob's matches cannot be ordered (a name without a number, or two with the
/// same numbers), when `expected` >= 0 and the count differs, or when a column is matched twice.
std::vector<int> selectColumns(const RawTable& table, const std::string& selector, int expected,
                               const std::string& what);

}  // namespace dynid
