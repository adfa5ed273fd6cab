#include "data/bags/bag.hpp"

#include <algorithm>
#include <filesystem>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/bags/bytes.hpp"
#include "data/bags/mcap.hpp"
#include "data/bags/ros1_bag.hpp"
#include "data/bags/rosbag2.hpp"

namespace dynid::bags {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// A ROS 2 MCAP file (CDR messages; other encodings are refused when their topic is asked for).
void readMcap(const std::string& file, const std::vector<std::string>& topics,
              const std::function<void(const BagMessage&)>& on_message) {
  McapReader reader(file);
  reader.read([&](const McapMessage& message) {
    const McapChannel& channel = reader.channels().at(message.channel_id);
    if (!topics.empty() && std::find(topics.begin(), topics.end(), channel.topic) == topics.end())
      return;
    const auto schema = reader.schemas().find(channel.schema_id);
    BagMessage m;
    m.topic = channel.topic;
    m.type = schema == reader.schemas().end() ? std::string_view() : schema->second.name;
    if (channel.message_encoding == "cdr")
      m.encoding = Encoding::kCdr;
    else if (channel.message_encoding == "ros1")
      m.encoding = Encoding::kRos1;
    else if (topics.empty())
      return;  // a topic in another encoding, not asked for
    else
      throw ParseError(
          file, 0, channel.topic,
          "message encoding '" + channel.message_encoding + "': dynid reads cdr (ROS 2) and ros1");
    m.receive_ns = static_cast<std::int64_t>(message.log_time);
    m.data = message.data;
    m.file = &file;
    m.offset = message.offset;
    on_message(m);
  });
}

/// A metadata.yaml's file names as paths in `dir`: plain names, or (metadata version < 4)
/// names prefixed with the directory's own name; nothing outside the directory.
std::vector<std::string> listedFiles(const fs::path& dir, const std::string& yaml_path) {
  ByteFile yaml(yaml_path);
  if (yaml.size() > (std::uint64_t{16} << 20))
    throw ParseError(yaml_path, 0, "", "larger than 16 MiB: not a bag's metadata.yaml");
  const std::string text = yaml.read(yaml.size(), "metadata");
  std::vector<std::string> files;
  const std::string own = fs::absolute(dir).lexically_normal().filename().string();
  for (std::string name : metadataFiles(text, yaml_path)) {
    if (const std::size_t slash = name.find('/');
        slash != std::string::npos && name.substr(0, slash) == own)
      name.erase(0, slash + 1);
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos)
      throw ParseError(yaml_path, 0, "relative_file_paths",
                       "'" + name + "' is not a file in the bag's directory");
    files.push_back((dir / name).string());
  }
  return files;
}

}  // namespace

bool isBag(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) {
    if (fs::exists(fs::path(path) / "metadata.yaml", error)) return true;
    for (const auto& entry : fs::directory_iterator(path, error))
      if (endsWith(entry.path().string(), ".db3") || endsWith(entry.path().string(), ".mcap"))
        return true;
    return false;
  }
  return endsWith(path, ".db3") || endsWith(path, ".mcap") || endsWith(path, ".bag");
}

std::vector<std::string> bagFiles(const std::string& path) {
  std::error_code error;
  if (!fs::is_directory(path, error)) return {path};
  const fs::path dir(path);
  if (const fs::path yaml = dir / "metadata.yaml"; fs::exists(yaml, error)) {
    std::vector<std::string> files = listedFiles(dir, yaml.string());
    if (!files.empty()) return files;
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().string();
    if (entry.is_regular_file(error) && (endsWith(name, ".db3") || endsWith(name, ".mcap")))
      files.push_back(name);
  }
  if (files.empty())
    throw InputError("'" + path + "' is a directory with no recording: no metadata.yaml " +
                     "listing files, and no .db3 or .mcap file");
  std::sort(files.begin(), files.end(), naturalLess);
  return files;
}

void readBag(const std::string& path, const std::vector<std::string>& topics,
             const std::function<void(const BagMessage&)>& on_message) {
  for (const std::string& file : bagFiles(path)) {
    if (endsWith(file, ".db3"))
      readSqliteBag(file, topics, on_message);
    else if (endsWith(file, ".mcap"))
      readMcap(file, topics, on_message);
    else if (endsWith(file, ".bag"))
      readRos1Bag(file, topics, on_message);
    else
      throw InputError("'" + file + "': not a recording dynid reads (.db3, .mcap or .bag)");
  }
}

}  // namespace dynid::bags
