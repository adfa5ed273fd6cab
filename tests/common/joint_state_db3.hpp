// sensor_msgs/JointState recordings for tests and benchmarks: messages encoded as ROS 2 CDR (little
// endian, XCDR1 alignment) and a rosbag2 SQLite file (.db3) written by SQLite itself; topics of
// other types take messages encoded elsewhere (tests/common/floating_bag.hpp). No gtest: the
// benchmarks compile this file too.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace dynid::test {

/// One JointState message as ROS 2 CDR: header stamp [ns], names, positions, velocities and
/// efforts, n of each (none of an array whose pointer is null). The returned bytes live until the
/// next call.
class CdrJointState {
 public:
  const std::string& encode(std::int64_t stamp_ns, const std::vector<std::string>& names,
                            const double* q, const double* dq, const double* tau);

 private:
  template <class T>
  void put(T v);
  void string(const std::string& s);
  std::string b_;
};

/// A rosbag2 SQLite recording of sensor_msgs/msg/JointState topics, written message by message in
/// one transaction; the file is complete after close() (or the destructor).
class JointStateDb3 {
 public:
  /// Creates `path` (replacing a file there) with these topics. Throws dynid::Error when SQLite
  /// fails.
  /// `types`: each topic's message type (e.g. sensor_msgs/msg/Imu); empty: JointState for all.
  explicit JointStateDb3(const std::string& path,
                         const std::vector<std::string>& topics = {"/joint_states"},
                         const std::vector<std::string>& types = {});
  JointStateDb3(const JointStateDb3&) = delete;
  JointStateDb3& operator=(const JointStateDb3&) = delete;
  ~JointStateDb3();
  /// One message on topics[topic]: stamped stamp_ns, received receive_ns (the recorder's clock).
  void add(std::int64_t stamp_ns, std::int64_t receive_ns, const std::vector<std::string>& names,
           const double* q, const double* dq, const double* tau, int topic = 0);
  /// One message already encoded (CDR) on topics[topic].
  void addEncoded(int topic, std::int64_t receive_ns, const std::string& bytes);
  void close();

 private:
  void check(int rc);
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  CdrJointState cdr_;
};

}  // namespace dynid::test
