// The logs wing's one seam: readLog turns one recording, whatever its format (a table, one file
// per signal, a ROS bag), into RawSignals
// (time, q, tau and, when logged, dq and ddq, one row per sample, in the file's own units, with
// the file and line of every row for messages). `dynid prepare` (prepare.hpp) starts from there.
// A new log format is one reader file beside raw_log.hpp and one branch of readLog
// (docs/ARCHITECTURE.md, "A new log format").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "data/scratch.hpp"

namespace dynid {

struct RawSignals;

/// Where the signals are: tables with column selectors (analysis/logs/raw_log.hpp's selectColumns),
/// or one file per signal (a value per line, n per sample).
struct LogSource {
  std::vector<std::string> tables;  // delimited tables, in order; empty: one file per signal
  std::string time_column = "1", q_columns, dq_columns, tau_columns;  // table selectors
  std::string time_file, q_file, dq_file, tau_file;                   // one file per signal
  int num_joints = 0;                 // 0: the q selector's count (tables) or required (files)
  bool current = false;               // the tau selector or file holds motor currents [A]
  std::string ddq_columns, ddq_file;  // logged accelerations (rare): a table selector or a file
  /// Recordings among `tables` (.mcap, .bag; analysis/logs/bag_log.hpp): their
  /// sensor_msgs/JointState topic (empty: the only one), the robot's joint names in order (empty:
  /// the first message's), and the stamp (header.stamp, or the time the recorder received it).
  std::string topic = "";
  std::vector<std::string> joint_names = {};
  /// The prefix the messages put before every one of joint_names (one arm of several: "left_");
  /// empty: the names themselves, or one prefix that fits every joint alone.
  std::string joint_prefix = "";
  bool receive_time = false;
  /// A recording whose JointState messages carry no effort: the torques (or currents) from the
  /// JointState efforts on a second topic of it, or from a table (its `time_column`, seconds on
  /// the recording's clock, and `tau_columns`), interpolated linearly at the position stamps.
  std::string effort_topic = "";
  std::string effort_table = "";
  /// Samples already in memory (Python's prepare(t=, q=, tau=)), read instead of any file.
  std::shared_ptr<const RawSignals> arrays = nullptr;
  /// Tables: leave out a row whose selected field is missing (empty, nan, inf: a logger's
  /// dropout), counted and warned about, instead of refusing the file.
  bool skip_missing = false;
  /// Tables: numbers written with ',' for the decimal point (fields separated by ';', tab or
  /// blanks), as European spreadsheets export them.
  bool decimal_comma = false;
};

/// The table columns each signal was read from, joint by joint (what a selector matched, in joint
/// order): recorded in prepare.json so a reader can check the joint order.
struct LogColumns {
  std::string time;
  std::vector<std::string> q, tau, dq, ddq;
};

/// One file's signals, one row per sample: time, q (n), tau (n), then dq (n) and ddq (n) when
/// logged. In one matrix (`values`), or, for a long recording read with a scratch directory, the
/// time alone in memory and the other columns in a scratch file (`spilled`, column c at c - 1).
/// Only the first `rows` rows are live (dropping samples compacts in place). Column c's live rows
/// are column(c), whichever holds them.
struct RawSignals {
  Eigen::MatrixXd values;  // every column; with `spilled`, the time column alone
  std::shared_ptr<ScratchColumns> spilled;
  Eigen::Index rows = 0;
  int n = 0;
  bool has_dq = false, has_ddq = false;
  int ddq_at = 0;                            // ddq's first column
  std::string tau_file;                      // the file holding tau (or the currents)
  std::function<int(Eigen::Index)> line_of;  // the file line of a raw row (before sorting)
  std::string file;                          // the file holding the time stamps
  LogColumns columns;                        // tables: the columns read (empty for files)
  /// The first data row's stamp, in the file's unit; values' time column holds each stamp minus
  /// it (so nanosecond epoch stamps keep their precision as doubles).
  long double time_origin = 0.0L;
  std::vector<std::string> warnings = {};  // what reading changed (prepare.json's warnings)
  long skipped_missing = 0;  // rows left out for a missing value (LogSource::skip_missing)
  auto time() const { return values.col(0).head(rows); }
  /// In memory only (not `spilled`): the signals as blocks.
  auto q() const { return values.block(0, 1, rows, n); }
  auto tau() const { return values.block(0, 1 + n, rows, n); }
  auto dq() const { return values.block(0, 1 + 2 * n, rows, n); }

  int numColumns() const {
    return spilled ? 1 + spilled->columns() : static_cast<int>(values.cols());
  }
  /// Live rows [first, first + count) of column c (all of them by default).
  Eigen::VectorXd column(int c, Eigen::Index first = 0, Eigen::Index count = -1) const;
  /// Column c's live rows become x (rows entries).
  void setColumn(int c, const Eigen::VectorXd& x);
  /// Keeps rows `kept` (indices of live rows, in the order given: increasing to drop rows, a
  /// permutation to sort them), column by column; rows becomes kept.size().
  void keep(const std::vector<Eigen::Index>& kept);
};

/// Recording `table` of `source` (a path in source.tables), or, with `table` empty, the
/// one-file-per-signal log (or source.arrays when given). Throws ParseError for a malformed file
/// (file, line, column) and InputError for a source that names too little (no joint count for
/// per-signal files, no q or tau) or selectors that do not match.
/// With `scratch_dir`, a table's or a recording's samples go to a scratch file there as they are
/// read (RawSignals::spilled; memory independent of its length), except a recording's whose
/// efforts come from a second topic or table (joined in memory). One-file-per-signal logs and
/// arrays stay in memory.
RawSignals readLog(const LogSource& source, const std::string& table,
                   const std::string& scratch_dir = "");

}  // namespace dynid
