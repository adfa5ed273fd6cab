// File output that never leaves a partial file, and number formatting that round-trips.
#pragma once

#include <string>

namespace dynid {

/// Writes `content` to `path` through a temporary file in the same directory and a rename, so
/// readers see the old file or the whole new one. A path that names a stream (a FIFO, or a
/// character device such as /dev/null or /dev/stdout) is written through instead, never replaced;
/// a directory or other special file is refused. Throws Error naming the path on failure (the
/// temporary is removed).
void writeFileAtomically(const std::string& path, const std::string& content);

/// Reads a whole file. Throws Error naming the path when it cannot be read.
std::string readFile(const std::string& path);

/// Shortest decimal form that parses back to exactly x ("0.1", "1e-300", "inf", "nan").
std::string formatDouble(double x);

/// Text with &, <, > and " escaped for XML and HTML attribute values and content.
std::string escapeXml(const std::string& text);

}  // namespace dynid
