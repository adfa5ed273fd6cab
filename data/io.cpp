#include "data/io.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <csignal>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "core/memory.hpp"

namespace dynid {

namespace {
// The open temporaries' paths, for removeLiveTemporaries in a signal handler: a fixed table of
// atomic pointers (no allocation, no lock). A writer beyond the table's size is not registered;
// its temporary survives a signal, as any does after SIGKILL (the next run ignores it).
constexpr int kSlots = 64;
std::atomic<const char*> live_temporaries[kSlots];

int registerTemporary(const char* path) {
  for (int k = 0; k < kSlots; ++k) {
    const char* expected = nullptr;
    if (live_temporaries[k].compare_exchange_strong(expected, path)) return k;
  }
  return -1;
}
void unregisterTemporary(int slot) {
  if (slot >= 0) live_temporaries[slot].store(nullptr);
}

// The inputs of the command (InputFileGuard): device and inode of every regular file read, and
// every input's path as first named, in the order first read (streams too).
std::mutex input_mutex;
bool inputs_guarded = false;
std::vector<std::pair<dev_t, ino_t>> input_files;
std::vector<CommandInput> input_paths;

void noteInput(const struct stat& st, const std::string& path) {
  const bool regular = S_ISREG(st.st_mode);
  const std::lock_guard<std::mutex> lock(input_mutex);
  if (!inputs_guarded) return;
  const auto id = std::make_pair(st.st_dev, st.st_ino);
  if (regular && std::find(input_files.begin(), input_files.end(), id) != input_files.end())
    return;  // read again (a second pass), or under another name: recorded once
  if (regular) input_files.push_back(id);
  input_paths.push_back({path, regular});
}

bool isInput(const struct stat& st) {
  const std::lock_guard<std::mutex> lock(input_mutex);
  return std::find(input_files.begin(), input_files.end(), std::make_pair(st.st_dev, st.st_ino)) !=
         input_files.end();
}

// PublishWindow's state: 0 closed, -1 open, > 0 open with that signal deferred.
std::atomic<int> publish_state{0};

/// `<path>.tmp.<pid>.<8 hex digits>`, fresh for each attempt.
std::string temporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  std::random_device device;
  const unsigned value = device() ^ (counter.fetch_add(1) * 0x9E3779B9u);
  char hex[9];
  std::snprintf(hex, sizeof(hex), "%08x", value);
  return path + ".tmp." + std::to_string(::getpid()) + "." + hex;
}

/// Removes `<path>.tmp.<pid>[.<suffix>]` files of processes that no longer exist: what a writer
/// killed by SIGKILL (or a power cut) left. Best effort: errors are ignored.
void removeStaleTemporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code ec;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    std::string digits = name.substr(prefix.size());
    if (const std::size_t dot = digits.find('.'); dot != std::string::npos) {
      const std::string suffix = digits.substr(dot + 1);
      if (suffix.empty() || suffix.find_first_not_of("0123456789abcdef") != std::string::npos)
        continue;
      digits.resize(dot);
    }
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
        digits.size() > 9)
      continue;
    const auto pid = static_cast<pid_t>(std::stol(digits));
    if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}
}  // namespace

void removeLiveTemporaries() noexcept {
  for (auto& slot : live_temporaries)
    if (const char* path = slot.load(); path != nullptr) ::unlink(path);
}

AtomicWriter::AtomicWriter(const std::string& path, ExistingTarget existing) : path_(path) {
  // The target's type decides: a regular file (or none) is replaced whole by a rename; a stream
  // (FIFO, character device) the user named is written through; anything else (a directory, a
  // socket, a block device) is refused. With kReplace a symbolic link is replaced, not followed.
  if (path == "-") {  // standard output, written through (a dup: closing it keeps stdout open)
    std::fflush(stdout);
    const int fd = ::dup(STDOUT_FILENO);
    file_ = fd < 0 ? nullptr : ::fdopen(fd, "wb");
    if (file_ == nullptr)
      throw Error(std::string("cannot write to standard output: ") + std::strerror(errno));
    return;
  }
  struct stat target {};
  const bool follow = existing != ExistingTarget::kReplace;
  const int found = follow ? ::stat(path.c_str(), &target) : ::lstat(path.c_str(), &target);
  bool stream = false;
  if (found == 0 && !S_ISREG(target.st_mode) && !(!follow && S_ISLNK(target.st_mode))) {
    stream = follow && (S_ISFIFO(target.st_mode) || S_ISCHR(target.st_mode));
    if (!stream)
      throw Error("cannot write '" + path + "': it exists and is not a regular file" +
                  (S_ISDIR(target.st_mode) ? " (a directory)" : ""));
  }
  if (found == 0 && S_ISREG(target.st_mode) && existing != ExistingTarget::kUpdate &&
      isInput(target))
    throw Error("cannot write '" + path + "': it is an input of this command (name another file)");
  if (stream) {
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) throw Error("cannot write '" + path + "': " + std::strerror(errno));
  } else {
    // Where the file system has them, an unnamed file (O_TMPFILE) in the target's directory: no
    // name exists until stage() links one, so a SIGKILL while writing leaves nothing behind.
    const std::filesystem::path target_path(path);
    const std::string dir =
        target_path.has_parent_path() ? target_path.parent_path().string() : std::string(".");
    // Naming it later takes /proc/self/fd (linkat's AT_EMPTY_PATH needs a privilege).
    int fd = ::access("/proc/self/fd", X_OK) == 0
                 ? ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666)
                 : -1;
    anonymous_ = fd >= 0;
    if (fd < 0) fd = openNamedTemporary();
    file_ = ::fdopen(fd, "wb");
    if (file_ == nullptr) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      if (!anonymous_) ::unlink(temporary_.c_str());
      unregisterTemporary(slot_);
      throw Error("cannot write '" + path + "': " + why);
    }
  }
  buffer_.reserve(kBuffer);
}

int AtomicWriter::openNamedTemporary() {
  // Created exclusively and never through a link: a file or link planted at the temporary's
  // name makes the attempt fail (EEXIST), and another name is drawn.
  // Registered before it is created: a signal's handler in between unlinks nothing, one after
  // unlinks it (the handler runs on the main thread; ThreadPool's workers block the signals).
  int fd = -1;
  for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
    unregisterTemporary(slot_);
    temporary_ = temporaryName(path_);
    slot_ = registerTemporary(temporary_.c_str());
    fd = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    const std::string why = std::strerror(errno);
    unregisterTemporary(slot_);
    slot_ = -1;
    temporary_.clear();
    throw Error("cannot write '" + path_ + "': " + why);
  }
  return fd;
}

void AtomicWriter::linkAnonymous(int fd) {
  // linkat through /proc/self/fd (AT_EMPTY_PATH would need CAP_DAC_READ_SEARCH); a name that
  // exists (planted, or another writer's) makes the attempt fail with EEXIST: another is drawn.
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  for (int attempt = 0; attempt < 16; ++attempt) {
    unregisterTemporary(slot_);
    temporary_ = temporaryName(path_);
    slot_ = registerTemporary(temporary_.c_str());
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary_.c_str(), AT_SYMLINK_FOLLOW) == 0)
      return;
    if (errno != EEXIST) break;
  }
  const std::string why = std::strerror(errno);
  unregisterTemporary(slot_);
  slot_ = -1;
  temporary_.clear();
  throw Error("cannot write '" + path_ + "': " + why);
}

AtomicWriter::~AtomicWriter() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
  unregisterTemporary(slot_);
}

void AtomicWriter::write(std::string_view text) {
  if (buffer_.size() + text.size() < kBuffer) {
    buffer_.append(text);
    return;
  }
  flush();
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

void AtomicWriter::flush() {
  if (buffer_.empty()) return;
  if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
    throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
  buffer_.clear();
}

void AtomicWriter::stage() {
  if (staged_) return;
  flush();
  const bool through = temporary_.empty() && !anonymous_;  // a stream, or standard output
  const bool flushed = std::fflush(file_) == 0 && (through || ::fsync(::fileno(file_)) == 0);
  if (flushed && anonymous_) {
    try {
      linkAnonymous(::fileno(file_));  // the content is whole: now it gets a name
    } catch (const Error&) {
      std::fclose(file_);
      file_ = nullptr;
      throw;
    }
  }
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  staged_ = true;
  if (!flushed || !closed) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
}

void AtomicWriter::commit() {
  if (committed_) return;
  stage();
  if (!temporary_.empty() && std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
  unregisterTemporary(slot_);
  slot_ = -1;
  if (!temporary_.empty()) removeStaleTemporaries(path_);
}

bool isInputFile(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && isInput(st);
}

InputFileGuard::InputFileGuard() {
  const std::lock_guard<std::mutex> lock(input_mutex);
  inputs_guarded = true;
  input_files.clear();
  input_paths.clear();
}

InputFileGuard::~InputFileGuard() {
  const std::lock_guard<std::mutex> lock(input_mutex);
  inputs_guarded = false;
  input_files.clear();
  input_paths.clear();
}

void noteInputFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISDIR(st.st_mode)) noteInput(st, path);
}

std::vector<CommandInput> commandInputs() {
  const std::lock_guard<std::mutex> lock(input_mutex);
  return input_paths;
}

namespace {
std::atomic<int> publish_depth{0};  // windows open (nested ones share the outermost)
}  // namespace

PublishWindow::PublishWindow() {
  if (publish_depth.fetch_add(1) == 0) publish_state.store(-1);
}

PublishWindow::~PublishWindow() {
  if (publish_depth.fetch_sub(1) != 1) return;
  const int deferred = publish_state.exchange(0);
  if (deferred > 0) std::raise(deferred);
}

bool deferSignalWhilePublishing(int signal) noexcept {
  int state = publish_state.load();
  while (state != 0) {
    if (state > 0) return true;  // one is deferred already
    if (publish_state.compare_exchange_weak(state, signal)) return true;
  }
  return false;
}

void writeFileAtomically(const std::string& path, const std::string& content,
                         ExistingTarget existing) {
  AtomicWriter out(path, existing);
  out.write(content);
  out.commit();
}

std::string readFile(const std::string& path, double max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  const std::unique_ptr<int, void (*)(int*)> closer(new int(fd), [](int* f) {
    ::close(*f);
    delete f;
  });
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw Error("cannot read '" + path + "': it is a directory");
  noteInput(st, path);
  std::string out;
  const bool regular = S_ISREG(st.st_mode);
  if (regular) {
    const auto size = static_cast<double>(st.st_size);
    if (size > max_bytes)
      throw InputError("'" + path + "' is " + formatBytes(size) + ", more than the " +
                       formatBytes(max_bytes) + " this file may be");
    requireMemory(size, "reading '" + path + "'");
    out.reserve(static_cast<std::size_t>(st.st_size));
  } else {
    max_bytes = std::min(max_bytes, kMaxDocumentBytes);
  }
  std::array<char, 1 << 16> buffer;
  while (true) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0) {
      if (errno == EINTR) continue;
      throw Error("cannot read '" + path + "': " + std::strerror(errno));
    }
    if (got == 0) break;
    if (static_cast<double>(out.size()) + static_cast<double>(got) > max_bytes)
      throw InputError("'" + path + "' holds more than " + formatBytes(max_bytes) +
                       (regular ? " (it grew while being read)"
                                : " (a stream is read up to that; save it to a file)"));
    out.append(buffer.data(), static_cast<std::size_t>(got));
  }
  return out;
}

LineReader::LineReader(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || S_ISDIR(st.st_mode)) {
    const std::string why = S_ISDIR(st.st_mode) ? "it is a directory" : std::strerror(errno);
    ::close(fd_);
    throw Error("cannot read '" + path + "': " + why);
  }
  noteInput(st, path);
  regular_ = S_ISREG(st.st_mode);
  size_at_open_ = static_cast<long long>(st.st_size);
  // A small file gets a block of its own size (fuzz targets read thousands of few-kB inputs).
  constexpr std::size_t kBlock = std::size_t{1} << 22;
  const std::size_t block =
      regular_ ? std::clamp<std::size_t>(static_cast<std::size_t>(st.st_size) + 1, 4096, kBlock)
               : kBlock;
  buffer_.resize(block);
}

LineReader::~LineReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool LineReader::fill() {
  if (eof_) return false;
  // Keep the unfinished line at the buffer's start; grow the buffer for a line longer than it.
  const std::size_t kept = stop_ - start_;
  if (start_ > 0) std::memmove(buffer_.data(), buffer_.data() + start_, kept);
  start_ = 0;
  stop_ = kept;
  if (kept == buffer_.size()) {
    if (buffer_.size() >= kMaxLineBytes)
      throw ParseError(path_, line_ + 1, "",
                       "a line longer than " + formatBytes(static_cast<double>(kMaxLineBytes)) +
                           ": not a text file (or a missing line break)");
    buffer_.resize(std::min(2 * buffer_.size(), kMaxLineBytes));
  }
  while (true) {
    const ssize_t got = ::read(fd_, buffer_.data() + stop_, buffer_.size() - stop_);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw Error("cannot read '" + path_ + "': " + std::strerror(errno));
    }
    if (got == 0) {
      eof_ = true;
      if (regular_) {
        struct stat st {};
        const long long now =
            ::fstat(fd_, &st) == 0 ? static_cast<long long>(st.st_size) : bytes_read_;
        if (bytes_read_ != size_at_open_ || now != size_at_open_)
          throw Error(
              "'" + path_ + "' changed while it was read: " + std::to_string(size_at_open_) +
              " bytes when opened, " + std::to_string(bytes_read_) + " read, " +
              std::to_string(now) + " now (a log still being written, or a copy cut short?)");
      }
      return false;
    }
    stop_ += static_cast<std::size_t>(got);
    bytes_read_ += got;
    return true;
  }
}

bool LineReader::next(std::string_view& line) {
  while (true) {
    const char* begin = buffer_.data() + start_;
    const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', stop_ - start_));
    if (newline != nullptr) {
      const std::size_t length = static_cast<std::size_t>(newline - begin);
      line = std::string_view(begin, length);
      start_ += length + 1;
      break;
    }
    if (!fill()) {
      if (start_ == stop_) return false;
      line = std::string_view(buffer_.data() + start_, stop_ - start_);  // no final newline
      start_ = stop_;
      break;
    }
  }
  ++line_;
  // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first line.
  if (line_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
  return true;
}

namespace {
/// The length of the UTF-8 sequence at text[i] (1 to 4) and its code point, or 0 when it is not
/// valid UTF-8 (a stray continuation byte, 0xf8..0xff, a truncated sequence, an overlong form, a
/// surrogate, or a code point past U+10FFFF).
std::size_t decodeUtf8(std::string_view text, std::size_t i, char32_t* code) {
  const auto c = static_cast<unsigned char>(text[i]);
  if (c < 0x80) {
    *code = c;
    return 1;
  }
  std::size_t length = 0;
  char32_t least = 0;
  if ((c & 0xe0) == 0xc0) {
    length = 2, *code = c & 0x1f, least = 0x80;
  } else if ((c & 0xf0) == 0xe0) {
    length = 3, *code = c & 0x0f, least = 0x800;
  } else if ((c & 0xf8) == 0xf0) {
    length = 4, *code = c & 0x07, least = 0x10000;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    const auto next = static_cast<unsigned char>(text[i + k]);
    if ((next & 0xc0) != 0x80) return 0;
    *code = (*code << 6) | (next & 0x3f);
  }
  if (*code < least || *code > 0x10ffff || (*code >= 0xd800 && *code <= 0xdfff)) return 0;
  return length;
}
}  // namespace

bool isPrintableUtf8(std::string_view text) {
  char32_t code = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = decodeUtf8(text, i, &code);
    if (length == 0 || code < 0x20 || code == 0x7f) return false;
    i += length;
  }
  return true;
}

std::size_t firstInvalidUtf8(std::string_view text) {
  char32_t code = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = decodeUtf8(text, i, &code);
    if (length == 0) return i;
    i += length;
  }
  return std::string_view::npos;
}

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::vector<std::string_view> splitFields(std::string_view line, char delimiter) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = line.find(delimiter, start);
    fields.push_back(line.substr(start, at == std::string_view::npos ? at : at - start));
    if (at == std::string_view::npos) break;
    start = at + 1;
  }
  return fields;
}

}  // namespace dynid
