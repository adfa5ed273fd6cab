#include "reports/output.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/errors.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

std::string& commandName() {
  static std::string name = "dynid";
  return name;
}

std::string manifestName() { return ".dynid-outputs-" + commandName(); }

/// A name an output set may hold or remove: a plain file name, never a path.
bool plainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

/// The names an earlier set recorded in `dir` (none when there is no valid record).
std::vector<std::string> previousSet(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  const std::string path = dir + "/" + manifestName();
  const auto status = std::filesystem::symlink_status(path, ec);
  if (ec || !std::filesystem::is_regular_file(status)) return names;
  // Read directly, not through readFile: the record is this command's own, not an input.
  if (std::filesystem::file_size(path, ec) > (1u << 20) || ec) return names;
  try {
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line) || line != "dynid output set") return names;
    while (std::getline(in, line))
      if (plainName(line) && line.rfind(".dynid-outputs", 0) != 0) names.push_back(line);
  } catch (const std::exception&) {
    names.clear();  // unreadable: remove nothing
  }
  return names;
}

}  // namespace

void OutputSet::setCommand(const std::string& command) {
  commandName() = plainName(command) ? command : "dynid";
}

OutputSet::OutputSet(std::string dir, bool replaces_previous)
    : dir_(std::move(dir)), replaces_previous_(replaces_previous) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw Error("cannot create the output directory '" + dir_ + "': " + ec.message());
}

AtomicWriter& OutputSet::stream(const std::string& name) {
  if (!plainName(name) || name.rfind(".dynid-outputs", 0) == 0)
    throw Error("'" + name + "' is not a file name an output set may hold");
  files_.push_back(std::make_unique<AtomicWriter>(dir_ + "/" + name, ExistingTarget::kReplace));
  names_.push_back(name);
  return *files_.back();
}

void OutputSet::add(const std::string& name, std::string_view content) {
  AtomicWriter& file = stream(name);
  file.write(content);
  file.stage();
}

void OutputSet::publish() {
  if (published_) return;
  std::string record = "dynid output set\n";
  for (const std::string& name : names_) record.append(name).append(1, '\n');
  std::vector<std::string> stale;
  if (replaces_previous_)
    for (const std::string& name : previousSet(dir_))
      if (std::find(names_.begin(), names_.end(), name) == names_.end()) stale.push_back(name);
  std::unique_ptr<AtomicWriter> manifest;
  if (replaces_previous_) {
    manifest =
        std::make_unique<AtomicWriter>(dir_ + "/" + manifestName(), ExistingTarget::kReplace);
    manifest->write(record);
  }
  for (auto& file : files_) file->stage();
  if (manifest) manifest->stage();
  {
    const PublishWindow window;  // every rename, or (SIGKILL aside) none
    for (auto& file : files_) file->commit();
    if (manifest) manifest->commit();
    for (const std::string& name : stale)
      if (!isInputFile(dir_ + "/" + name)) ::unlink((dir_ + "/" + name).c_str());
  }
  published_ = true;
}

void writeReportFiles(const std::string& dir,
                      const std::vector<std::pair<std::string, std::string>>& files) {
  OutputSet set(dir);
  for (const auto& [name, content] : files) set.add(name, content);
  set.publish();
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
