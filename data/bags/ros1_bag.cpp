#include "data/bags/ros1_bag.hpp"

#include <bzlib.h>

#include <algorithm>
#include <map>

#include "core/errors.hpp"
#include "core/memory.hpp"
#include "data/bags/bytes.hpp"

namespace dynid::bags {

namespace {

constexpr std::string_view kVersion = "#ROSBAG V2.0\n";
constexpr std::uint32_t kMaxRecord = 1u << 31;  // 2 GiB: beyond it a length is damage

enum Op : std::uint8_t {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kBagChunk = 0x05,
  kConnection = 0x07,
};

/// A record's header fields (name=value, values binary).
std::map<std::string, std::string_view, std::less<>> fieldsOf(Cursor& header) {
  std::map<std::string, std::string_view, std::less<>> out;
  while (!header.done()) {
    const std::string_view field = header.string("header field");
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) header.fail("header field", "a field without '='");
    out.emplace(std::string(field.substr(0, eq)), field.substr(eq + 1));
  }
  return out;
}

template <class T>
T fieldAs(const std::map<std::string, std::string_view, std::less<>>& fields, const char* name,
          const Cursor& at) {
  const auto it = fields.find(name);
  if (it == fields.end() || it->second.size() != sizeof(T))
    at.fail(name, it == fields.end() ? "missing" : "of the wrong size");
  T value;
  std::memcpy(&value, it->second.data(), sizeof(T));
  return value;
}

std::string decompress(const Cursor& at, std::string_view compression, std::string_view data,
                       std::uint32_t size) {
  // Robot data never compresses 1000:1; a size beyond that is a damaged field, refused before
  // the allocation it would cause.
  if (static_cast<double>(size) > 1000.0 * static_cast<double>(data.size()) + 1048576.0)
    at.fail("size", "a chunk of " + std::to_string(data.size()) + " bytes claims " +
                        std::to_string(size) + " uncompressed (more than 1000:1: damaged)");
  requireMemory(static_cast<double>(size),
                at.file() + ": a chunk of " + std::to_string(size) + " bytes");
  std::string out(size, '\0');
  if (compression == "none") {
    out.assign(data);
  } else if (compression == "bz2") {
    unsigned int length = size;
    const int result =
        BZ2_bzBuffToBuffDecompress(out.data(), &length, const_cast<char*>(data.data()),
                                   static_cast<unsigned int>(data.size()), 0, 0);
    if (result != BZ_OK)
      at.fail("chunk", "bz2 decompression failed (code " + std::to_string(result) + ")");
    out.resize(length);
  } else if (compression == "lz4") {
    if (const std::string error = lz4Frame(data, out); !error.empty()) at.fail("chunk", error);
  } else {
    at.fail("compression", "unknown compression '" + std::string(compression) +
                               "' (dynid reads none, bz2 and lz4)");
  }
  if (out.size() != size)
    at.fail("chunk", std::to_string(out.size()) + " bytes after decompression, the chunk says " +
                         std::to_string(size) + " (truncated or damaged)");
  return out;
}

struct Connection {
  std::string topic, type;
};

}  // namespace

void readRos1Bag(const std::string& file, const std::vector<std::string>& topics,
                 const std::function<void(const BagMessage&)>& on_message) {
  ByteFile in(file);
  if (in.read(std::min<std::uint64_t>(kVersion.size(), in.size()), "version") != kVersion)
    throw ParseError(file, 0, "version",
                     "at byte 0: not a ROS 1 bag of format 2.0 (the first line is not #ROSBAG "
                     "V2.0)");
  std::map<std::uint32_t, Connection> connections;
  // One record: its header fields and data; `records` reads a run of them (the file, a chunk).
  const auto records = [&](Cursor& c, auto&& self) -> void {
    while (!c.done()) {
      Cursor header = c.sub(c.get<std::uint32_t>("header length"), "header");
      const auto fields = fieldsOf(header);
      const std::uint32_t data_length = c.get<std::uint32_t>("data length");
      Cursor data = c.sub(data_length, "data");
      const auto op = fieldAs<std::uint8_t>(fields, "op", header);
      if (op == kConnection) {
        const auto id = fieldAs<std::uint32_t>(fields, "conn", header);
        Connection& conn = connections[id];
        conn.topic = std::string(fields.count("topic") ? fields.find("topic")->second : "");
        const auto details = fieldsOf(data);  // the connection header: type, md5sum, ...
        if (const auto type = details.find("type"); type != details.end())
          conn.type = std::string(type->second);
      } else if (op == kMessageData) {
        const auto id = fieldAs<std::uint32_t>(fields, "conn", header);
        const auto it = connections.find(id);
        if (it == connections.end())
          header.fail("conn", "a message on connection " + std::to_string(id) +
                                  ", which no connection record before it defines");
        if (!topics.empty() &&
            std::find(topics.begin(), topics.end(), it->second.topic) == topics.end())
          continue;
        const auto time = fieldAs<std::uint64_t>(fields, "time", header);
        BagMessage m;
        m.topic = it->second.topic;
        m.type = it->second.type;
        m.encoding = Encoding::kRos1;
        m.receive_ns = static_cast<std::int64_t>(time & 0xffffffffu) * 1000000000 +
                       static_cast<std::int64_t>(time >> 32);
        m.data = data.rest();
        m.file = &file;
        m.offset = data.offset();
        on_message(m);
      } else if (op == kBagChunk) {
        const auto compression = fields.find("compression");
        if (compression == fields.end()) header.fail("compression", "missing");
        const auto size = fieldAs<std::uint32_t>(fields, "size", header);
        if (size > kMaxRecord) header.fail("size", "a chunk above 2 GiB");
        const std::string plain = decompress(data, compression->second, data.rest(), size);
        Cursor inner(plain, file, data.offset());
        self(inner, self);
      }
      // Bag header, index data, chunk info: not needed to read the messages in order.
    }
  };
  // Records at the top level, one at a time: a chunk is read whole, never the file.
  while (!in.atEnd()) {
    const std::uint64_t at = in.offset();
    const std::string lengths = in.read(4, "header length");
    std::uint32_t header_length = 0;
    std::memcpy(&header_length, lengths.data(), 4);
    if (header_length > kMaxRecord || header_length > in.remaining())
      throw ParseError(file, 0, "header length",
                       "at byte " + std::to_string(at) + ": a header of " +
                           std::to_string(header_length) + " bytes, past the end of the file");
    std::string record = lengths + in.read(header_length, "header");
    const std::string data_length_bytes = in.read(4, "data length");
    std::uint32_t data_length = 0;
    std::memcpy(&data_length, data_length_bytes.data(), 4);
    if (data_length > kMaxRecord || data_length > in.remaining())
      throw ParseError(file, 0, "data length",
                       "at byte " + std::to_string(at) + ": data of " +
                           std::to_string(data_length) + " bytes, past the end of the file");
    record += data_length_bytes;
    record += in.read(data_length, "data");
    Cursor c(record, file, at);
    records(c, records);
  }
}

}  // namespace dynid::bags
