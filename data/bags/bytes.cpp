#include "data/bags/bytes.hpp"

#include <sys/stat.h>

#include <cerrno>

#include "core/errors.hpp"

namespace dynid::bags {

ByteFile::ByteFile(const std::string& path) : path_(path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error("cannot read '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw ParseError(
        path, 0, "",
        S_ISDIR(st.st_mode) ? "is a directory, not a log file" : "is not a regular file");
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) throw Error("cannot read '" + path + "': " + std::strerror(errno));
  size_ = static_cast<std::uint64_t>(st.st_size);
}

ByteFile::~ByteFile() {
  if (file_ != nullptr) std::fclose(file_);
}

std::string ByteFile::read(std::uint64_t n, const char* field) {
  if (n > remaining())
    throw ParseError(path_, 0, field,
                     "at byte " + std::to_string(offset_) + ": needs " + std::to_string(n) +
                         " bytes, the file ends after " + std::to_string(remaining()) +
                         " (truncated)");
  std::string out(static_cast<std::size_t>(n), '\0');
  if (n > 0 && std::fread(out.data(), 1, out.size(), file_) != out.size())
    throw Error("cannot read '" + path_ + "' at byte " + std::to_string(offset_) + ": " +
                std::strerror(errno));
  offset_ += n;
  return out;
}

void ByteFile::skip(std::uint64_t n) { seek(offset_ + n); }

void ByteFile::seek(std::uint64_t offset) {
  if (offset > size_)
    throw ParseError(
        path_, 0, "",
        "at byte " + std::to_string(offset_) + ": a jump past the end of the file (truncated)");
  if (::fseeko(file_, static_cast<off_t>(offset), SEEK_SET) != 0)
    throw Error("cannot read '" + path_ + "': " + std::strerror(errno));
  offset_ = offset;
}

void Cursor::fail(const char* field, const std::string& what) const {
  throw ParseError(*file_, 0, field, "at byte " + std::to_string(offset()) + ": " + what);
}

}  // namespace dynid::bags
