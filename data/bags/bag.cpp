#include "data/bags/bag.hpp"

#include <algorithm>

#include "core/errors.hpp"
#include "data/bags/mcap.hpp"
#include "data/bags/ros1_bag.hpp"

namespace dynid::bags {

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

}  // namespace

bool isBag(const std::string& path) { return endsWith(path, ".mcap") || endsWith(path, ".bag"); }

void readBag(const std::string& path, const std::vector<std::string>& topics,
             const std::function<void(const BagMessage&)>& on_message) {
  if (endsWith(path, ".mcap"))
    readMcap(path, topics, on_message);
  else if (endsWith(path, ".bag"))
    readRos1Bag(path, topics, on_message);
  else
    throw InputError("'" + path + "': not a recording dynid reads (.mcap or .bag)");
}

}  // namespace dynid::bags
