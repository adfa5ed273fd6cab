// rosbag2's own files (ROS 2): the SQLite storage (.db3: tables `topics` and `messages`, as
// rosbag2_storage_sqlite3 creates them, read with Debian's libsqlite3) and the bag directory's
// metadata.yaml (which files, in which order). The MCAP storage is data/bags/mcap.hpp.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "data/bags/bag.hpp"

struct sqlite3;

namespace dynid::bags {

/// The files a metadata.yaml lists under `relative_file_paths`, in order, as written (rosbag2
/// writes a block list: `  relative_file_paths:` then `    - name_0.db3` lines). `file` names the
/// yaml in errors. Throws ParseError for a list item that is not a plain or quoted scalar.
std::vector<std::string> metadataFiles(std::string_view yaml, const std::string& file);

/// Every message of the rosbag2 SQLite database `db` on `topics` (all when empty), by receive
/// time then row, as rosbag2 plays them; `file` names it in errors. Messages in a serialization
/// format other than cdr are refused when their topic is asked for, skipped otherwise. Throws
/// ParseError naming the file, the table and the row for what is not a rosbag2 database or is
/// damaged.
void readSqliteBag(sqlite3* db, const std::string& file, const std::vector<std::string>& topics,
                   const std::function<void(const BagMessage&)>& on_message);

/// The same for the .db3 file at `path`, opened read-only and immutable (nothing is written
/// beside it, no lock taken).
void readSqliteBag(const std::string& path, const std::vector<std::string>& topics,
                   const std::function<void(const BagMessage&)>& on_message);

}  // namespace dynid::bags
