// File output that never leaves a partial file, and number formatting that round-trips.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace dynid {

/// A file written piece by piece with writeFileAtomically's guarantees: through a temporary in
/// the same directory, renamed over `path` by commit(); a stream target (FIFO, character device)
/// is written through; a directory or other special file is refused. Destroyed without commit
/// (an exception on the way), the temporary is removed and the target untouched. A commit also
/// removes the target's stale temporaries (`<path>.tmp.<pid>` of processes that no longer exist:
/// what a SIGKILL left). Throws Error naming the path on failure.
class AtomicWriter {
 public:
  explicit AtomicWriter(const std::string& path);
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;
  ~AtomicWriter();
  void write(std::string_view text);  // buffered
  void commit();                      // flush, sync, rename; at most once

 private:
  void flush();
  static constexpr std::size_t kBuffer = 1 << 20;
  std::string path_, temporary_;  // temporary_ empty: written through
  std::FILE* file_ = nullptr;
  std::string buffer_;
  bool committed_ = false;
  int slot_ = -1;  // this temporary's slot in the registry removeLiveTemporaries reads
};

/// Removes every temporary an AtomicWriter of this process has open (the targets are left as they
/// were). Async-signal-safe: for a SIGTERM or SIGINT handler, before the process dies.
void removeLiveTemporaries() noexcept;

/// Writes `content` to `path` through a temporary file in the same directory and a rename, so
/// readers see the old file or the whole new one. A path that names a stream (a FIFO, or a
/// character device such as /dev/null or /dev/stdout) is written through instead, never replaced;
/// a directory or other special file is refused. Throws Error naming the path on failure (the
/// temporary is removed).
void writeFileAtomically(const std::string& path, const std::string& content);

/// The most a stream (a pipe, a device: its size unknown in advance) or a document (JSON, URDF)
/// is read: 1 GiB, far above any model, settings file or checkpoint dynid writes.
inline constexpr double kMaxDocumentBytes = 1073741824.0;

/// Reads a whole file: a regular file of at most `max_bytes` that fits in memory
/// (core/memory.hpp), or a stream (a pipe or device) up to min(max_bytes, kMaxDocumentBytes).
/// Throws Error naming the path when it cannot be read or is a directory, InputError naming it
/// when it is larger than that or than the memory this process may use.
std::string readFile(const std::string& path, double max_bytes = kMaxDocumentBytes);

/// Shortest decimal form that parses back to exactly x ("0.1", "1e-300", "inf", "nan").
std::string formatDouble(double x);

/// True when `text` is valid UTF-8 (no overlong forms, surrogates or code points past U+10FFFF)
/// without control characters (below U+0020, or DEL): what a name (robot, link, joint, column)
/// must be to appear in dynid's JSON, XML and HTML outputs.
bool isPrintableUtf8(std::string_view text);

/// The offset of the first byte of `text` that does not start a valid UTF-8 sequence, or npos.
std::size_t firstInvalidUtf8(std::string_view text);

/// Text with &, <, > and " escaped for XML and HTML attribute values and content.
std::string escapeXml(const std::string& text);

}  // namespace dynid
