#include "data/scratch.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/errors.hpp"

namespace dynid {

namespace {

/// An unnamed file in `dir`: O_TMPFILE where the file system has it, else a random name created
/// exclusively (never through a link planted there) and unlinked at once. -1 with errno set.
int unnamedFile(const std::string& dir) {
#ifdef O_TMPFILE
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
  if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) return -1;
#endif
  std::random_device device;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const std::string path =
        dir + "/.dynid-scratch." + std::to_string(::getpid()) + "." + std::to_string(device());
    const int named =
        ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (named >= 0) {
      ::unlink(path.c_str());
      return named;
    }
    if (errno != EEXIST) return -1;
  }
  return -1;
}

}  // namespace

ScratchColumns::ScratchColumns(const std::string& dir, int columns, std::int64_t rows)
    : dir_(dir), columns_(columns), rows_(rows) {
  if (columns < 0 || rows < 0) throw Error("scratch columns: a negative size");
  fd_ = unnamedFile(dir);
  if (fd_ < 0) throw Error("cannot make a scratch file in '" + dir + "': " + std::strerror(errno));
}

ScratchColumns::~ScratchColumns() {
  if (fd_ >= 0) ::close(fd_);
}

template <typename Io>
void ScratchColumns::eachBlock(int column, std::int64_t first, std::int64_t count, Io io) const {
  constexpr auto kDouble = static_cast<std::int64_t>(sizeof(double));
  for (std::int64_t done = 0; done < count;) {
    const std::int64_t row = first + done, block = row / kBlockRows, within = row % kBlockRows;
    const std::int64_t part = std::min(count - done, kBlockRows - within);
    io(static_cast<off_t>(((block * columns_ + column) * kBlockRows + within) * kDouble), done,
       part);
    done += part;
  }
}

void ScratchColumns::write(int column, std::int64_t first, const double* values,
                           std::int64_t count) {
  if (column < 0 || column >= columns_ || first < 0 || count < 0)
    throw Error("scratch columns: rows out of range");
  eachBlock(column, first, count, [&](off_t at, std::int64_t index, std::int64_t part) {
    const char* from = reinterpret_cast<const char*>(values + index);
    auto left = static_cast<std::size_t>(part) * sizeof(double);
    while (left > 0) {
      const ssize_t done = ::pwrite(fd_, from, left, at);
      if (done < 0 && errno == EINTR) continue;
      if (done <= 0)
        throw Error("cannot write the scratch file in '" + dir_ +
                    "': " + (done < 0 ? std::strerror(errno) : "no space left"));
      from += done;
      at += done;
      left -= static_cast<std::size_t>(done);
    }
  });
  if (first + count > rows_)
    rows_ = first + count;  // only then: concurrent writes within the rows share nothing
}

void ScratchColumns::read(int column, std::int64_t first, double* values,
                          std::int64_t count) const {
  if (column < 0 || column >= columns_ || first < 0 || count < 0 || first + count > rows_)
    throw Error("scratch columns: rows out of range");
  eachBlock(column, first, count, [&](off_t at, std::int64_t index, std::int64_t part) {
    char* to = reinterpret_cast<char*>(values + index);
    auto left = static_cast<std::size_t>(part) * sizeof(double);
    while (left > 0) {
      const ssize_t done = ::pread(fd_, to, left, at);
      if (done < 0 && errno == EINTR) continue;
      if (done < 0)
        throw Error("cannot read the scratch file in '" + dir_ + "': " + std::strerror(errno));
      if (done == 0) {  // never written, past the file's end: zeros
        std::memset(to, 0, left);
        return;
      }
      to += done;
      at += done;
      left -= static_cast<std::size_t>(done);
    }
  });
}

std::string nearestExistingDirectory(const std::string& path) {
  std::filesystem::path at =
      path.empty() ? std::filesystem::path(".") : std::filesystem::path(path);
  std::error_code error;
  while (true) {
    if (std::filesystem::is_directory(at, error)) return at.string();
    if (!at.has_parent_path() || at.parent_path() == at) return ".";
    at = at.parent_path();
  }
}

}  // namespace dynid
