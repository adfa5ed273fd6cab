// Where every document goes: files written whole or not at all (data/io.hpp's
// writeFileAtomically), or standard output for "-".
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "data/io.hpp"

namespace dynid {

/// The files one command writes into its output directory, published together: each is written
/// whole into its own temporary beside its target first, then publish() renames them all into
/// place inside a PublishWindow (a SIGTERM, SIGHUP or Ctrl-C waits for it), so the directory
/// holds the previous run's set or this one's, never a mix. The set's names are recorded in
/// `<dir>/.dynid-outputs-<command>`; publishing removes the files that the same command's earlier
/// set recorded there and this one does not write (a previous prepare's validate.csv beside a new
/// train.csv), never another command's files nor an input of this one. A symbolic link at a
/// target is replaced, never followed. Destroyed unpublished (an exception, an interrupted run),
/// every temporary is removed and the directory is as it was.
class OutputSet {
 public:
  /// The command whose sets are being written ("prepare"; the CLI sets it once; default "dynid").
  static void setCommand(const std::string& command);
  /// Creates `dir` (and its parents). `replaces_previous`: false for a directory that collects
  /// files from several runs (batch runs/), whose earlier files stay. Throws Error naming it.
  explicit OutputSet(std::string dir, bool replaces_previous = true);
  /// Writes `content` as file `name` (a plain file name) of the set.
  void add(const std::string& name, std::string_view content);
  /// A file of the set written piece by piece by the caller (staged at publish).
  AtomicWriter& stream(const std::string& name);
  /// Renames every file into place; at most once. Throws Error naming a file that cannot be.
  void publish();
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  bool replaces_previous_;
  std::vector<std::unique_ptr<AtomicWriter>> files_;
  std::vector<std::string> names_;
  bool published_ = false;
};

/// An OutputSet of these (file name, content) pairs, published. Throws Error naming the path
/// that cannot be written.
void writeReportFiles(const std::string& dir,
                      const std::vector<std::pair<std::string, std::string>>& files);

/// Checks, before a command starts its work, that `dir` can become its output directory: an
/// existing directory, or a path whose nearest existing ancestor is a writable directory. Creates
/// nothing. Throws Error naming the path otherwise (a long run must not fail at its end).
void checkOutputDirectory(const std::string& dir);

/// Writes `content` to `path` atomically, or to standard output when `path` is "-". Returns
/// whether it went to a file.
bool writeOutput(const std::string& path, const std::string& content);

}  // namespace dynid
