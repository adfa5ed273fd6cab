#include "data/io.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"

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
}  // namespace

void removeLiveTemporaries() noexcept {
  for (auto& slot : live_temporaries)
    if (const char* path = slot.load(); path != nullptr) ::unlink(path);
}

AtomicWriter::AtomicWriter(const std::string& path) : path_(path) {
  // The target's type decides: a regular file (or none) is replaced whole by a rename; a stream
  // (FIFO, character device) is written through; anything else (a directory, a socket, a block
  // device) is refused.
  struct stat target {};
  std::string open_path = path;
  if (::stat(path.c_str(), &target) == 0 && !S_ISREG(target.st_mode)) {
    if (!S_ISFIFO(target.st_mode) && !S_ISCHR(target.st_mode))
      throw Error("cannot write '" + path + "': it exists and is not a regular file" +
                  (S_ISDIR(target.st_mode) ? " (a directory)" : ""));
  } else {
    temporary_ = path + ".tmp." + std::to_string(::getpid());
    open_path = temporary_;
  }
  if (!temporary_.empty()) slot_ = registerTemporary(temporary_.c_str());
  file_ = std::fopen(open_path.c_str(), "wb");
  if (file_ == nullptr) {
    unregisterTemporary(slot_);
    throw Error("cannot write '" + path + "': " + std::strerror(errno));
  }
  buffer_.reserve(kBuffer);
}

AtomicWriter::~AtomicWriter() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_ && !temporary_.empty()) std::remove(temporary_.c_str());
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

void AtomicWriter::commit() {
  if (committed_) return;
  flush();
  const bool flushed =
      std::fflush(file_) == 0 && (temporary_.empty() || ::fsync(::fileno(file_)) == 0);
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed) throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
  if (!temporary_.empty() && std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw Error("cannot write '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  AtomicWriter out(path);
  out.write(content);
  out.commit();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw Error("cannot read '" + path + "'");
  return s.str();
}

std::string formatDouble(double x) {
  std::array<char, 32> buffer;
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
  return std::string(buffer.data(), result.ptr);
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

}  // namespace dynid
