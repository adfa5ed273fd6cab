// libFuzzer target: rosbag2's files (data/bags/rosbag2.hpp). An input that starts with SQLite's
// magic is opened as a database from memory (read-only) and read as a rosbag2 .db3, every message
// decoded as a CDR JointState; any other input is read as a bag directory's metadata.yaml.
#include <sqlite3.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string_view>

#include "core/errors.hpp"
#include "data/bags/ros_messages.hpp"
#include "data/bags/rosbag2.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  static constexpr std::string_view kMagic("SQLite format 3\0", 16);
  try {
    if (input.substr(0, kMagic.size()) != kMagic) {
      for (const std::string& name : dynid::bags::metadataFiles(input, "metadata.yaml"))
        if (name.size() > size) __builtin_trap();  // a name larger than the file
      return 0;
    }
    sqlite3* raw = nullptr;
    if (sqlite3_open_v2(":memory:", &raw, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
      sqlite3_close(raw);
      return 0;
    }
    const std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db(raw, &sqlite3_close);
    auto* copy = static_cast<unsigned char*>(sqlite3_malloc64(size));
    if (copy == nullptr) return 0;
    std::memcpy(copy, data, size);
    if (sqlite3_deserialize(
            raw, "main", copy, static_cast<sqlite3_int64>(size), static_cast<sqlite3_int64>(size),
            SQLITE_DESERIALIZE_FREEONCLOSE | SQLITE_DESERIALIZE_READONLY) != SQLITE_OK)
      return 0;
    const std::string file = "fuzz.db3";
    dynid::bags::readSqliteBag(raw, file, {}, [&](const dynid::bags::BagMessage& m) {
      if (m.data.size() > size) __builtin_trap();  // a message larger than the file
      dynid::bags::JointStateMessage js;
      try {
        dynid::bags::decodeJointStateCdr(m.data, file, m.offset, js);
        if (8 * (js.position.size() + js.velocity.size() + js.effort.size()) > m.data.size())
          __builtin_trap();
      } catch (const dynid::Error&) {
      }
    });
  } catch (const dynid::Error&) {
  }
  return 0;
}
