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

/// Writes `content` to `path` atomically, or to standard output when `path` is "-". Returns
/// whether it went to a file.
bool writeOutput(const std::string& path, const std::string& content);

}  // namespace dynid
