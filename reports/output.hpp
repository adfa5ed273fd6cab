// Where every document goes: files written whole or not at all (data/io.hpp's
// writeFileAtomically), or standard output for "-".
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace dynid {

/// Creates `dir` (and its parents) and writes each (file name, content) into it atomically.
/// Throws Error naming the path that cannot be written.
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
