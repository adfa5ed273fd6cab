// Reading binary logs safely: a file read in order with its offset known, and a cursor over bytes
// that refuses to run past their end. Every error is a ParseError naming the file, the field and
// the byte offset. Little-endian hosts only (as MCAP, ROS 1 bags and CDR as ROS writes it).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace dynid::bags {

/// A file read front to back.
class ByteFile {
 public:
  /// Throws Error when the file cannot be opened, ParseError when it is not a regular file.
  explicit ByteFile(const std::string& path);
  ~ByteFile();
  ByteFile(const ByteFile&) = delete;
  ByteFile& operator=(const ByteFile&) = delete;

  /// The next `n` bytes (ParseError naming `field` when the file ends first).
  std::string read(std::uint64_t n, const char* field);
  void skip(std::uint64_t n);
  void seek(std::uint64_t offset);
  std::uint64_t offset() const { return offset_; }
  std::uint64_t size() const { return size_; }
  std::uint64_t remaining() const { return size_ - offset_; }
  bool atEnd() const { return offset_ >= size_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0, offset_ = 0;
};

/// Bytes read in order; `base` is their offset in the file (for messages).
class Cursor {
 public:
  Cursor(std::string_view bytes, const std::string& file, std::uint64_t base)
      : bytes_(bytes), file_(&file), base_(base) {}

  template <class T>
  T get(const char* field) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), field);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string_view bytes(std::uint64_t n, const char* field) {
    need(n, field);
    const std::string_view out = bytes_.substr(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return out;
  }
  /// A uint32 length, then that many bytes.
  std::string_view string(const char* field) { return bytes(get<std::uint32_t>(field), field); }
  /// The next `n` bytes as a cursor of their own.
  Cursor sub(std::uint64_t n, const char* field) {
    const std::uint64_t at = offset();
    return Cursor(bytes(n, field), *file_, at);
  }
  /// Skips to a multiple of `alignment` from `origin` (CDR aligns from its payload's start).
  void align(std::size_t alignment, std::size_t origin, const char* field) {
    const std::size_t from = at_ - origin;
    const std::size_t pad = (alignment - from % alignment) % alignment;
    need(pad, field);
    at_ += pad;
  }
  std::string_view rest() {
    const std::string_view out = bytes_.substr(at_);
    at_ = bytes_.size();
    return out;
  }
  bool done() const { return at_ >= bytes_.size(); }
  std::size_t position() const { return at_; }
  std::size_t remaining() const { return bytes_.size() - at_; }
  std::uint64_t offset() const { return base_ + at_; }
  const std::string& file() const { return *file_; }

  /// ParseError naming `field` and the current offset.
  [[noreturn]] void fail(const char* field, const std::string& what) const;

 private:
  void need(std::uint64_t n, const char* field) const {
    if (n > bytes_.size() - at_)
      fail(field, "needs " + std::to_string(n) + " bytes, " + std::to_string(bytes_.size() - at_) +
                      " are left (truncated or damaged)");
  }

  std::string_view bytes_;
  const std::string* file_;
  std::uint64_t base_;
  std::size_t at_ = 0;
};

/// Decompresses one LZ4 frame (as MCAP and ROS 1's roslz4 write them) into `out`, which holds the
/// expected size beforehand and is cut to what was written. Returns an error text, empty when the
/// frame decoded.
std::string lz4Frame(std::string_view in, std::string& out);

}  // namespace dynid::bags
