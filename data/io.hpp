// File output that never leaves a partial file, and number formatting that round-trips.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace dynid {

/// How AtomicWriter treats what is already at its path.
enum class ExistingTarget {
  /// A path the user named: a symbolic link is followed; a stream (FIFO, character device such
  /// as /dev/stdout) is written through, never replaced.
  kFollow,
  /// A path dynid chose inside an output directory: a symbolic link there is replaced, never
  /// followed; anything but a regular file is refused.
  kReplace,
  /// A file the command reads and rewrites (a checkpoint): as kFollow, and it may be an input.
  kUpdate,
};

/// A file written piece by piece with writeFileAtomically's guarantees: through a temporary in
/// the same directory, renamed over `path` by commit(); a directory or other special file is
/// refused. The temporary is an unnamed file (O_TMPFILE) where the file system has them, linked
/// to `<path>.tmp.<pid>.<random>` only by stage() once its content is whole and synced, so a
/// SIGKILL while writing leaves no file; elsewhere it is created under that name at once. Either
/// way the name is made exclusively: never through a link or file planted there. Destroyed without
/// commit (an exception on the way), the temporary is removed and the target untouched. A commit
/// also removes the target's stale temporaries (of processes that no longer exist: what a SIGKILL
/// left). While an InputFileGuard exists, a target that is one of the command's input files is
/// refused. The path "-" is standard output, written through (a user who pipes a command's one
/// output file takes the stream as it comes). Throws Error naming the path on failure.
class AtomicWriter {
 public:
  explicit AtomicWriter(const std::string& path, ExistingTarget existing = ExistingTarget::kFollow);
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;
  ~AtomicWriter();
  void write(std::string_view text);  // buffered
  /// Flushes, syncs and closes the temporary: the content is whole on disk, not yet in place.
  void stage();
  /// Renames the staged temporary over the path (stages first when needed); at most once.
  void commit();
  const std::string& path() const { return path_; }

 private:
  void flush();
  int openNamedTemporary();    // creates temporary_ exclusively; returns its descriptor
  void linkAnonymous(int fd);  // gives the unnamed temporary its name, exclusively
  static constexpr std::size_t kBuffer = 1 << 20;
  std::string path_, temporary_;  // temporary_ empty and not anonymous_: written through
  bool anonymous_ = false;        // an unnamed temporary (O_TMPFILE) until stage()
  std::FILE* file_ = nullptr;
  std::string buffer_;
  bool staged_ = false, committed_ = false;
  int slot_ = -1;  // this temporary's slot in the registry removeLiveTemporaries reads
};

/// While one exists (the CLI holds one for the whole command), every file read through readFile
/// or LineReader is remembered by device and inode, and AtomicWriter refuses to replace any of
/// them: a command never overwrites its own input, by whatever path it is named. Not nested.
class InputFileGuard {
 public:
  InputFileGuard();
  ~InputFileGuard();
  InputFileGuard(const InputFileGuard&) = delete;
  InputFileGuard& operator=(const InputFileGuard&) = delete;
};

/// True when an InputFileGuard exists and `path` (not followed when a link) is one of the files
/// it remembers.
bool isInputFile(const std::string& path);

/// An input of the command, as its documents' provenance records it: the path as first named
/// (relative paths are the working directory's), and whether it is a regular file (else a stream:
/// a pipe, a device, standard input).
struct CommandInput {
  std::string path;
  bool regular = false;
};

/// A file read by other means than readFile or LineReader (a recording's own reader, an SQLite
/// database), remembered as those are while an InputFileGuard exists.
void noteInputFile(const std::string& path);

/// Every input read while the InputFileGuard exists, in the order first read, each file once
/// (empty without a guard).
std::vector<CommandInput> commandInputs();

/// While one exists, a set of outputs is being renamed into place: SIGTERM, SIGHUP or SIGINT
/// handlers that call deferSignalWhilePublishing wait for it, so an interrupted command leaves
/// the whole old set or the whole new one. On destruction a deferred signal is raised again.
class PublishWindow {
 public:
  PublishWindow();
  ~PublishWindow();
  PublishWindow(const PublishWindow&) = delete;
  PublishWindow& operator=(const PublishWindow&) = delete;
};
/// For a signal handler (async-signal-safe): true when a PublishWindow is open, the signal then
/// recorded to be raised when it closes; false when the handler should act now.
bool deferSignalWhilePublishing(int signal) noexcept;

/// Removes every temporary an AtomicWriter of this process has open (the targets are left as they
/// were). Async-signal-safe: for a SIGTERM or SIGINT handler, before the process dies.
void removeLiveTemporaries() noexcept;

/// Writes `content` to `path` through a temporary file in the same directory and a rename, so
/// readers see the old file or the whole new one. A path that names a stream (a FIFO, or a
/// character device such as /dev/null or /dev/stdout) is written through instead, never replaced;
/// a directory or other special file is refused. Throws Error naming the path on failure (the
/// temporary is removed).
void writeFileAtomically(const std::string& path, const std::string& content,
                         ExistingTarget existing = ExistingTarget::kFollow);

/// The most a stream (a pipe, a device: its size unknown in advance) or a document (JSON, URDF)
/// is read: 1 GiB, far above any model, settings file or checkpoint dynid writes.
inline constexpr double kMaxDocumentBytes = 1073741824.0;

/// Reads a whole file: a regular file of at most `max_bytes` that fits in memory
/// (core/memory.hpp), or a stream (a pipe or device) up to min(max_bytes, kMaxDocumentBytes).
/// Throws Error naming the path when it cannot be read or is a directory, InputError naming it
/// when it is larger than that or than the memory this process may use.
std::string readFile(const std::string& path, double max_bytes = kMaxDocumentBytes);

/// The fields of one delimited line (a CSV row, a column list), as views into it: split at every
/// `delimiter`, nothing trimmed; n delimiters give n + 1 fields (an empty line: one empty field).
/// The one field splitter of dynid's readers (datasets, raw tables, monitor streams).
std::vector<std::string_view> splitFields(std::string_view line, char delimiter = ',');

/// A text file read line by line in blocks: memory independent of the file's size. Lines are
/// returned without their '\n' (a '\r' before it is kept), the UTF-8 byte-order mark of the first
/// line dropped, a last line without a newline returned too. A regular file that grows or shrinks
/// while it is read is an error at its end (a log still being written, a copy cut short), never a
/// silently shorter input.
class LineReader {
 public:
  /// Opens `path` (a regular file, a pipe or a device). Throws Error naming it when it cannot be
  /// read or is a directory.
  explicit LineReader(const std::string& path);
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  ~LineReader();

  /// The next line in `line` (valid until the next call) and true; false at the end of the file.
  /// Throws ParseError for a line longer than kMaxLineBytes (a binary file, a missing line break),
  /// Error when reading fails or when a regular file's size changed since it was opened.
  bool next(std::string_view& line);
  /// The 1-based number of the line last returned (0 before the first).
  int lineNumber() const { return line_; }
  const std::string& path() const { return path_; }

  static constexpr std::size_t kMaxLineBytes = std::size_t{1} << 26;  // 64 MiB

 private:
  bool fill();  // reads more after the kept bytes; false at the end of the file
  std::string path_;
  int fd_ = -1;
  bool regular_ = false;
  long long size_at_open_ = 0, bytes_read_ = 0;
  std::string buffer_;
  std::size_t start_ = 0, stop_ = 0;  // unreturned bytes: buffer_[start_, stop_)
  bool eof_ = false;
  int line_ = 0;
};

/// True when `text` is valid UTF-8 (no overlong forms, surrogates or code points past U+10FFFF)
/// without control characters (below U+0020, or DEL): what a name (robot, link, joint, column)
/// must be to appear in dynid's JSON, XML and HTML outputs.
bool isPrintableUtf8(std::string_view text);

/// The offset of the first byte of `text` that does not start a valid UTF-8 sequence, or npos.
std::size_t firstInvalidUtf8(std::string_view text);

/// Text with &, <, > and " escaped for XML and HTML attribute values and content.
std::string escapeXml(const std::string& text);

}  // namespace dynid
