#include "data/bags/rosbag2.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <memory>

#include "core/errors.hpp"

namespace dynid::bags {

std::vector<std::string> metadataFiles(std::string_view yaml, const std::string& file) {
  std::vector<std::string> out;
  bool inside = false;
  std::size_t indent = 0;
  int line_number = 0;
  while (!yaml.empty()) {
    const std::size_t end = std::min(yaml.find('\n'), yaml.size());
    std::string_view line = yaml.substr(0, end);
    yaml.remove_prefix(std::min(end + 1, yaml.size()));
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::size_t first = line.find_first_not_of(' ');
    if (first == std::string_view::npos || line[first] == '#') continue;
    constexpr std::string_view kKey = "relative_file_paths:";
    if (!inside) {
      if (line.substr(first, kKey.size()) == kKey) {
        inside = true;
        indent = first;
        std::string_view rest = line.substr(first + kKey.size());
        rest.remove_prefix(std::min(rest.find_first_not_of(' '), rest.size()));
        if (rest.substr(0, 2) == "[]") return out;
        if (!rest.empty() && rest.front() != '#')
          throw ParseError(file, line_number, "relative_file_paths",
                           "dynid reads the block list rosbag2 writes ('- name' lines)");
      }
      continue;
    }
    // rosbag2 indents the items under the key, or writes them at the key's indent.
    if (first < indent || line[first] != '-') break;  // the list ended
    std::string_view name = line.substr(first + 1);
    name.remove_prefix(std::min(name.find_first_not_of(' '), name.size()));
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'') &&
        name.back() == name.front())
      name = name.substr(1, name.size() - 2);
    else if (name.empty() || name.front() == '"' || name.front() == '\'' || name.front() == '[' ||
             name.front() == '{')
      throw ParseError(file, line_number, "relative_file_paths", "an item that is not a file name");
    out.emplace_back(name);
  }
  return out;
}

namespace {

struct Statement {
  sqlite3_stmt* raw = nullptr;
  ~Statement() { sqlite3_finalize(raw); }
};

std::string columnText(sqlite3_stmt* statement, int column) {
  const unsigned char* s = sqlite3_column_text(statement, column);
  return s == nullptr
             ? std::string()
             : std::string(reinterpret_cast<const char*>(s),
                           static_cast<std::size_t>(sqlite3_column_bytes(statement, column)));
}

/// A path as an SQLite URI (RFC 3986 percent-encoding of all but unreserved characters and '/').
std::string fileUri(const std::string& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  // An absolute path after an empty authority ("file:///a"), so that "//a" is not read as a host.
  std::string uri = !path.empty() && path.front() == '/' ? "file://" : "file:";
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if ((u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') ||
        std::string_view("-._~/").find(c) != std::string_view::npos) {
      uri += c;
    } else {
      uri += '%';
      uri += kHex[u >> 4];
      uri += kHex[u & 15];
    }
  }
  return uri + "?immutable=1";
}

}  // namespace

void readSqliteBag(sqlite3* db, const std::string& file, const std::vector<std::string>& topics,
                   const std::function<void(const BagMessage&)>& on_message) {
  const auto fail = [&](const std::string& table, const std::string& what) {
    const int code = sqlite3_errcode(db) & 0xff;  // the primary result code
    const bool damaged = code == SQLITE_CORRUPT || code == SQLITE_NOTADB || code == SQLITE_IOERR;
    throw ParseError(file, 0, table,
                     (damaged ? "a damaged or truncated file, or not SQLite" : what) +
                         " (SQLite: " + sqlite3_errmsg(db) + ")");
  };
  struct Topic {
    std::string name, type, format;
  };
  std::map<sqlite3_int64, Topic> by_id;
  {
    Statement query;
    if (sqlite3_prepare_v2(db, "SELECT id, name, type, serialization_format FROM topics", -1,
                           &query.raw, nullptr) != SQLITE_OK)
      fail("topics", "not a rosbag2 database: no readable topics table");
    int step = 0;
    while ((step = sqlite3_step(query.raw)) == SQLITE_ROW)
      by_id[sqlite3_column_int64(query.raw, 0)] = {
          columnText(query.raw, 1), columnText(query.raw, 2), columnText(query.raw, 3)};
    if (step != SQLITE_DONE) fail("topics", "the topics table cannot be read (damaged?)");
  }
  Statement query;
  if (sqlite3_prepare_v2(db,
                         "SELECT id, topic_id, timestamp, data FROM messages "
                         "ORDER BY timestamp, id",
                         -1, &query.raw, nullptr) != SQLITE_OK)
    fail("messages", "not a rosbag2 database: no readable messages table");
  int step = 0;
  while ((step = sqlite3_step(query.raw)) == SQLITE_ROW) {
    const sqlite3_int64 row = sqlite3_column_int64(query.raw, 0);
    const sqlite3_int64 topic_id = sqlite3_column_int64(query.raw, 1);
    const auto it = by_id.find(topic_id);
    if (it == by_id.end())
      throw ParseError(file, 0, "messages",
                       "row " + std::to_string(row) + ": topic id " + std::to_string(topic_id) +
                           ", which the topics table does not hold");
    const Topic& topic = it->second;
    if (!topics.empty() && std::find(topics.begin(), topics.end(), topic.name) == topics.end())
      continue;
    if (topic.format != "cdr") {
      if (topics.empty()) continue;  // a topic in another format, not asked for
      throw ParseError(file, 0, topic.name,
                       "serialization format '" + topic.format + "': dynid reads cdr (ROS 2)");
    }
    if (sqlite3_column_type(query.raw, 3) != SQLITE_BLOB &&
        sqlite3_column_type(query.raw, 3) != SQLITE_NULL)
      throw ParseError(file, 0, "messages",
                       "row " + std::to_string(row) + ": its data is not a blob");
    const void* blob = sqlite3_column_blob(query.raw, 3);
    const int size = sqlite3_column_bytes(query.raw, 3);
    BagMessage m;
    m.topic = topic.name;
    m.type = topic.type;
    m.encoding = Encoding::kCdr;
    m.receive_ns = sqlite3_column_int64(query.raw, 2);
    if (blob != nullptr)
      m.data = std::string_view(static_cast<const char*>(blob), static_cast<std::size_t>(size));
    m.file = &file;
    m.offset = static_cast<std::uint64_t>(row);
    on_message(m);
  }
  if (step != SQLITE_DONE) fail("messages", "the messages table cannot be read (damaged?)");
}

void readSqliteBag(const std::string& path, const std::vector<std::string>& topics,
                   const std::function<void(const BagMessage&)>& on_message) {
  sqlite3* raw = nullptr;
  const int opened =
      sqlite3_open_v2(fileUri(path).c_str(), &raw, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
  const std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db(raw, &sqlite3_close);
  if (opened != SQLITE_OK)
    throw ParseError(path, 0, "",
                     std::string("cannot be opened as an SQLite database: ") +
                         (raw != nullptr ? sqlite3_errmsg(raw) : "out of memory"));
  readSqliteBag(raw, path, topics, on_message);
}

}  // namespace dynid::bags
