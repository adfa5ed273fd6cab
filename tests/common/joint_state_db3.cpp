#include "tests/common/joint_state_db3.hpp"

#include <sqlite3.h>

#include <cstring>
#include <filesystem>

#include "core/errors.hpp"

namespace dynid::test {

template <class T>
void CdrJointState::put(T v) {
  while ((b_.size() - 4) % sizeof(T) != 0) b_.push_back('\0');  // aligned after the 4-byte header
  b_.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

void CdrJointState::string(const std::string& s) {
  put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
  b_.append(s);
  b_.push_back('\0');
}

const std::string& CdrJointState::encode(std::int64_t stamp_ns,
                                         const std::vector<std::string>& names, const double* q,
                                         const double* dq, const double* tau) {
  const auto n = static_cast<std::uint32_t>(names.size());
  b_.assign("\x00\x01\x00\x00", 4);  // CDR, little endian
  put<std::int32_t>(static_cast<std::int32_t>(stamp_ns / 1000000000));
  put<std::uint32_t>(static_cast<std::uint32_t>(stamp_ns % 1000000000));
  string("");  // frame_id
  put<std::uint32_t>(n);
  for (const std::string& name : names) string(name);
  for (const double* v : {q, dq, tau}) {
    put<std::uint32_t>(v ? n : 0);
    if (v)
      for (std::uint32_t j = 0; j < n; ++j) put<double>(v[j]);
  }
  return b_;
}

void JointStateDb3::check(int rc) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE && rc != SQLITE_ROW)
    throw Error(std::string("sqlite: ") + sqlite3_errmsg(db_));
}

JointStateDb3::JointStateDb3(const std::string& path, const std::vector<std::string>& topics,
                             const std::vector<std::string>& types) {
  std::filesystem::remove(path);
  check(sqlite3_open(path.c_str(), &db_));
  check(sqlite3_exec(db_,
                     "PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;"
                     "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT "
                     "NOT NULL, serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT "
                     "NULL);"
                     "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
                     "timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
                     "CREATE INDEX timestamp_idx ON messages (timestamp ASC);",
                     nullptr, nullptr, nullptr));
  sqlite3_stmt* insert_topic = nullptr;
  check(sqlite3_prepare_v2(db_, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", -1, &insert_topic,
                           nullptr));
  for (std::size_t i = 0; i < topics.size(); ++i) {
    sqlite3_bind_int(insert_topic, 1, static_cast<int>(i + 1));
    sqlite3_bind_text(insert_topic, 2, topics[i].c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(insert_topic, 3,
                      i < types.size() ? types[i].c_str() : "sensor_msgs/msg/JointState", -1,
                      SQLITE_TRANSIENT);
    check(sqlite3_step(insert_topic));
    sqlite3_reset(insert_topic);
  }
  sqlite3_finalize(insert_topic);
  check(sqlite3_exec(db_, "BEGIN;", nullptr, nullptr, nullptr));
  check(sqlite3_prepare_v2(db_, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                           -1, &insert_, nullptr));
}

void JointStateDb3::addEncoded(int topic, std::int64_t receive_ns, const std::string& bytes) {
  sqlite3_bind_int(insert_, 1, topic + 1);
  sqlite3_bind_int64(insert_, 2, receive_ns);
  sqlite3_bind_blob(insert_, 3, bytes.data(), static_cast<int>(bytes.size()), SQLITE_STATIC);
  check(sqlite3_step(insert_));
  sqlite3_reset(insert_);
}

void JointStateDb3::add(std::int64_t stamp_ns, std::int64_t receive_ns,
                        const std::vector<std::string>& names, const double* q, const double* dq,
                        const double* tau, int topic) {
  addEncoded(topic, receive_ns, cdr_.encode(stamp_ns, names, q, dq, tau));
}

void JointStateDb3::close() {
  if (!db_) return;
  sqlite3_finalize(insert_);
  insert_ = nullptr;
  const int rc = sqlite3_exec(db_, "COMMIT;", nullptr, nullptr, nullptr);
  sqlite3_close(db_);
  db_ = nullptr;
  if (rc != SQLITE_OK) throw Error("sqlite: the recording's transaction did not commit");
}

JointStateDb3::~JointStateDb3() {
  try {
    close();
  } catch (const Error&) {  // a destructor does not throw; close() reports it when called
  }
}

}  // namespace dynid::test
