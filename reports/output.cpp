#include "reports/output.hpp"

#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "core/errors.hpp"
#include "data/io.hpp"

namespace dynid {

void writeReportFiles(const std::string& dir,
                      const std::vector<std::pair<std::string, std::string>>& files) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error("cannot create the output directory '" + dir + "': " + ec.message());
  for (const auto& [name, content] : files) writeFileAtomically(dir + "/" + name, content);
}

void checkOutputDirectory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path at = fs::absolute(fs::path(dir), ec);
  if (ec) throw Error("cannot write into '" + dir + "': " + ec.message());
  if (fs::exists(fs::symlink_status(at, ec)) && !fs::is_directory(at, ec))
    throw Error("cannot write into '" + dir + "': it exists and is not a directory");
  while (!fs::exists(at, ec) && at.has_parent_path() && at != at.parent_path())
    at = at.parent_path();
  if (!fs::is_directory(at, ec))
    throw Error("cannot create the output directory '" + dir + "': '" + at.string() +
                "' is not a directory");
  if (::access(at.c_str(), W_OK | X_OK) != 0)
    throw Error("cannot create the output directory '" + dir + "': '" + at.string() +
                "' is not writable");
}

bool writeOutput(const std::string& path, const std::string& content) {
  if (path == "-") {
    std::cout << content;
    return false;
  }
  writeFileAtomically(path, content);
  return true;
}

}  // namespace dynid
