#include "data/bags/bytes.hpp"

#include <lz4frame.h>
#include <sys/stat.h>

#include <cerrno>
#include <memory>

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

std::string lz4Frame(std::string_view in, std::string& out) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION)))
    return "cannot start an lz4 decompression";
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> owner(
      context, &LZ4F_freeDecompressionContext);
  std::size_t written = 0, read = 0;
  while (read < in.size() && written < out.size()) {
    std::size_t dst = out.size() - written, src = in.size() - read;
    const std::size_t hint =
        LZ4F_decompress(context, out.data() + written, &dst, in.data() + read, &src, nullptr);
    if (LZ4F_isError(hint)) return std::string("lz4: ") + LZ4F_getErrorName(hint);
    written += dst;
    read += src;
    if (hint == 0 || (dst == 0 && src == 0)) break;  // the frame's end, or no progress
  }
  out.resize(written);
  return "";
}

void Cursor::fail(const char* field, const std::string& what) const {
  throw ParseError(*file_, 0, field, "at byte " + std::to_string(offset()) + ": " + what);
}

}  // namespace dynid::bags
