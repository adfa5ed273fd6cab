// ROS 2 recordings written by other people's writers, read back:
//   - rosbag2's own test bags (tests/data/bags/fixtures/rosbag2/, from the rosbag2 repository):
//     split bags with metadata.yaml in SQLite and MCAP give the message counts their metadata
//     records, topic by topic;
//   - JointState fixtures from the MCAP project's writer and SQLite (tools/mcap/joint_states.mjs:
//     zstd, lz4 and unchunked MCAP, a .db3 and a split .db3 directory) give the written values;
// and damage (truncation, a foreign file, a missing table or topic, a metadata.yaml pointing
// outside its directory) is refused with the file, never a crash.
#include "data/bags/rosbag2.hpp"

#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/bags/bag.hpp"
#include "data/bags/ros_messages.hpp"
#include "data/io.hpp"
#include "tests/common/error_text.hpp"
#include "tests/common/fixtures.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::bags {
namespace {

namespace fs = std::filesystem;
using test::bagFixtures;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// metadata.yaml's topics_with_message_count, read independently of the reader under test:
/// rosbag2 writes each entry's topic name and its count, in either order.
std::map<std::string, int> recordedCounts(const fs::path& yaml) {
  const std::regex name(R"(^\s+name: (\S+)$)"), count(R"(^\s+(- )?message_count: (\d+)$)");
  std::map<std::string, int> counts;
  std::istringstream lines(readText(yaml));
  std::string pending_name;
  int pending_count = -1;
  bool in_topics = false;
  for (std::string line; std::getline(lines, line);) {
    if (!in_topics) {
      in_topics = line.find("topics_with_message_count:") != std::string::npos;
      continue;
    }
    if (line.size() > 2 && line.compare(0, 2, "  ") == 0 && line[2] != ' ' && line[2] != '-')
      break;  // the next key of rosbag2_bagfile_information
    std::smatch m;
    if (std::regex_match(line, m, name)) pending_name = m[1];
    if (std::regex_match(line, m, count)) pending_count = std::stoi(m[2]);
    if (!pending_name.empty() && pending_count >= 0) {
      if (pending_count > 0) counts[pending_name] = pending_count;  // a topic with no message
      pending_name.clear();
      pending_count = -1;
    }
  }
  return counts;
}

TEST(Rosbag2, SplitBagsFromRosbag2GiveTheCountsTheirMetadataRecords) {
  for (const char* storage : {"sqlite3", "mcap"})
    for (const char* bag : {"wbag", "talker", "cdr_test"}) {
      const fs::path dir = bagFixtures() / "rosbag2" / storage / bag;
      SCOPED_TRACE(dir.string());
      const std::map<std::string, int> want = recordedCounts(dir / "metadata.yaml");
      ASSERT_FALSE(want.empty());
      std::map<std::string, int> got;
      std::map<std::string, std::int64_t> last_receive;
      const std::string* file = nullptr;
      readBag(dir.string(), {}, [&](const BagMessage& m) {
        ++got[std::string(m.topic)];
        if (m.file != file) last_receive.clear(), file = m.file;
        // Each file in receive order (SQLite: by timestamp; rosbag2's MCAP: as recorded).
        if (std::string(storage) == "sqlite3") {
          EXPECT_GE(m.receive_ns, last_receive[""]) << m.topic;
        }
        last_receive[""] = m.receive_ns;
      });
      EXPECT_EQ(got, want);
    }
  // The split bag's files in metadata order; the per-file topic ids differ (the first file
  // numbers AAA 1, the others HHH 1) and every file's own table is used.
  const std::vector<std::string> files =
      bagFiles((bagFixtures() / "rosbag2/sqlite3/wbag").string());
  ASSERT_EQ(files.size(), 5u);
  for (std::size_t i = 0; i < files.size(); ++i)
    EXPECT_EQ(fs::path(files[i]).filename(), "wbag_" + std::to_string(i) + ".db3");
  int empty = 0;
  readBag((bagFixtures() / "rosbag2/sqlite3/empty_bag").string(), {},
          [&](const BagMessage&) { ++empty; });
  EXPECT_EQ(empty, 0);
}

TEST(Rosbag2, JointStatesFromTheMcapWriterAndSqliteReadBackExactly) {
  const std::vector<std::string> names = {"joint2", "joint1", "gripper"};
  const double number[] = {2.0, 1.0, 3.0};
  for (const char* name : {"joint_states_zstd.mcap", "joint_states_lz4.mcap",
                           "joint_states_plain.mcap", "joint_states.db3", "joint_states_split"}) {
    const std::string path = (bagFixtures() / "ros2" / name).string();
    SCOPED_TRACE(path);
    EXPECT_TRUE(isBag(path));
    int k = 0, chatter = 0;
    readBag(path, {}, [&](const BagMessage& m) {
      if (m.topic == "/chatter") {
        EXPECT_EQ(m.type, "std_msgs/msg/String");
        ++chatter;
        return;
      }
      EXPECT_EQ(m.topic, "/joint_states");
      EXPECT_EQ(m.type, kJointStateRos2);
      EXPECT_EQ(m.encoding, Encoding::kCdr);
      JointStateMessage js;
      decodeJointStateCdr(m.data, *m.file, m.offset, js);
      EXPECT_EQ(js.stamp_ns, 1700000000LL * 1000000000 + k * 1000000LL);
      EXPECT_EQ(m.receive_ns, js.stamp_ns + 250000);  // the writer's 250 us latency
      EXPECT_EQ(js.name, names);
      ASSERT_EQ(js.position.size(), 3u);
      for (int j = 0; j < 3; ++j) {
        // JavaScript's Math.sin/cos (V8's fdlibm) may differ from glibc's in the last bit.
        EXPECT_NEAR(js.position[j], 0.1 * number[j] * std::sin(0.01 * k), 1e-16);
        EXPECT_NEAR(js.velocity[j], 0.001 * number[j] * std::cos(0.01 * k), 1e-18);
        EXPECT_EQ(js.effort[j], 2.0 * number[j] + 0.5 * k);
      }
      ++k;
    });
    EXPECT_EQ(k, 200);
    EXPECT_EQ(chatter, 4);
    int only = 0;
    readBag(path, {"/chatter"}, [&](const BagMessage&) { ++only; });
    EXPECT_EQ(only, 4);
  }
}

TEST(Rosbag2, MetadataListsTheFilesInOrder) {
  EXPECT_EQ(metadataFiles("rosbag2_bagfile_information:\n  relative_file_paths:\n    - b_0.db3\n"
                          "    - 'b_1.db3'\n  starting_time:\n    nanoseconds_since_epoch: 0\n",
                          "m.yaml"),
            (std::vector<std::string>{"b_0.db3", "b_1.db3"}));
  // Items at the key's own indent (rosbag2 of Foxy and Humble), CRLF line ends, a comment.
  EXPECT_EQ(metadataFiles("x:\r\n  relative_file_paths:  # files\r\n  - \"a.mcap\"\r\n"
                          "  duration: 1\r\n",
                          "m.yaml"),
            (std::vector<std::string>{"a.mcap"}));
  EXPECT_TRUE(metadataFiles("x:\n  relative_file_paths: []\n", "m.yaml").empty());
  EXPECT_TRUE(metadataFiles("", "m.yaml").empty());
  EXPECT_NE(test::errorText([] {
              metadataFiles("  relative_file_paths: [a.db3]\n", "m.yaml");
            }).find("m.yaml:1"),
            std::string::npos);
  EXPECT_NE(test::errorText([] {
              metadataFiles("  relative_file_paths:\n    - [a]\n", "m.yaml");
            }).find("m.yaml:2"),
            std::string::npos);
}

TEST(Rosbag2, ADirectorysFilesAreItsOwnAndInNaturalOrder) {
  const fs::path dir = test::tempPath("bag_dir");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path db = bagFixtures() / "ros2/joint_states.db3";
  // No metadata.yaml: the .db3 and .mcap files in natural order.
  for (const char* name : {"run_10.db3", "run_2.db3", "run_1.db3"}) fs::copy_file(db, dir / name);
  writeFileAtomically((dir / "notes.txt").string(), "not a bag");
  std::vector<std::string> names;
  for (const std::string& f : bagFiles(dir.string()))
    names.push_back(fs::path(f).filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"run_1.db3", "run_2.db3", "run_10.db3"}));
  // rosbag2 before metadata version 4 prefixed the names with the directory's own name.
  writeFileAtomically(
      (dir / "metadata.yaml").string(),
      "  relative_file_paths:\n    - " + dir.filename().string() + "/run_2.db3\n    - run_1.db3\n");
  names.clear();
  for (const std::string& f : bagFiles(dir.string()))
    names.push_back(fs::path(f).filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"run_2.db3", "run_1.db3"}));
  // Nothing outside the directory.
  for (const char* outside : {"../joint_states.db3", "/etc/passwd", "other/run_1.db3", ".."}) {
    writeFileAtomically((dir / "metadata.yaml").string(),
                        std::string("  relative_file_paths:\n    - ") + outside + "\n");
    EXPECT_NE(test::errorText([&] { bagFiles(dir.string()); }).find("not a file in the bag's"),
              std::string::npos)
        << outside;
  }
  // Names SQLite's URIs give a meaning to ('?', '#', '%', a leading "//") are only names.
  const std::string odd = (dir / "a b?c#d%41.db3").string();
  fs::copy_file(db, odd);
  for (const std::string& path : {odd, "/" + odd}) {
    int messages = 0;
    readBag(path, {}, [&](const BagMessage&) { ++messages; });
    EXPECT_EQ(messages, 204) << path;
  }
  fs::remove_all(dir);
  fs::create_directories(dir);
  EXPECT_FALSE(isBag(dir.string()));
  EXPECT_THROW(bagFiles(dir.string()), InputError);
}

TEST(Rosbag2, DamagedAndForeignDatabasesAreRefusedWithTheFile) {
  const std::string good = readText(bagFixtures() / "ros2/joint_states.db3");
  const std::string path = test::tempPath("damaged.db3");
  const auto readAll = [&] { readBag(path, {}, [](const BagMessage&) {}); };
  // Truncations at 64 points: refused (the pages a query needs are missing) or, where only
  // free pages were cut, read; never a crash.
  int refused = 0;
  for (int i = 0; i < 64; ++i) {
    const std::size_t at = good.size() * static_cast<std::size_t>(i) / 64;
    writeFileAtomically(path, good.substr(0, at));
    try {
      readAll();
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
      ++refused;
    }
  }
  EXPECT_GT(refused, 32);
  writeFileAtomically(path, "#ROSBAG V2.0\nnot sqlite");
  EXPECT_NE(test::errorText(readAll).find("or not SQLite (SQLite: file is not a database)"),
            std::string::npos);
  // An SQLite database that is not rosbag2's, and one whose message names a topic it lacks.
  fs::remove(path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE t(x INTEGER);", nullptr, nullptr, nullptr), SQLITE_OK);
  EXPECT_NE(test::errorText([&] {
              readSqliteBag(db, path, {}, [](const BagMessage&) {});
            }).find("no readable topics table"),
            std::string::npos);
  ASSERT_EQ(sqlite3_exec(db,
                         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, "
                         "serialization_format TEXT);"
                         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, "
                         "timestamp INTEGER, data BLOB);"
                         "INSERT INTO topics VALUES (1, '/js', 'sensor_msgs/msg/JointState', "
                         "'ros1');"
                         "INSERT INTO messages VALUES (7, 3, 10, x'00');",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  EXPECT_NE(test::errorText([&] {
              readSqliteBag(db, path, {}, [](const BagMessage&) {});
            }).find("row 7: topic id 3"),
            std::string::npos);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE messages SET topic_id = 1;", nullptr, nullptr, nullptr),
            SQLITE_OK);
  int read = 0;
  readSqliteBag(db, path, {}, [&](const BagMessage&) { ++read; });
  EXPECT_EQ(read, 0);  // a topic in another format is skipped when not asked for ...
  EXPECT_NE(test::errorText([&] {
              readSqliteBag(db, path, {"/js"}, [](const BagMessage&) {});
            }).find("serialization format 'ros1'"),
            std::string::npos);  // ... and refused when it is
  sqlite3_close(db);
}

}  // namespace
}  // namespace dynid::bags
