#include "reports/output.hpp"

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

bool writeOutput(const std::string& path, const std::string& content) {
  if (path == "-") {
    std::cout << content;
    return false;
  }
  writeFileAtomically(path, content);
  return true;
}

}  // namespace dynid
