// ROS 1 bags (format 2.0, http://wiki.ros.org/Bags/Format/2.0): records of a header (name=value
// fields) and data; chunks uncompressed, bz2 (Debian's libbz2) or lz4 (roslz4 writes LZ4 frames;
// Debian's liblz4). Read front to back, chunk by chunk; the index records are not needed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "data/bags/bag.hpp"

namespace dynid::bags {

/// Calls `on_message` for every message on `topics` (all when empty), in file order. Throws
/// ParseError naming the file and byte offset of a wrong version line, a record or field past its
/// end, a chunk that does not decompress to its stated size, an unknown compression, or a message
/// on a connection not defined before it.
void readRos1Bag(const std::string& file, const std::vector<std::string>& topics,
                 const std::function<void(const BagMessage&)>& on_message);

}  // namespace dynid::bags
