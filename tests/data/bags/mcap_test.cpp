// The MCAP reader against damage: chunks (none or zstd) read back, and truncated, corrupted,
// unknown and oversized input refused with the file and the byte offset, never a crash. Files
// from the MCAP project's own writer: mcap_conformance_test.cpp and rosbag2_test.cpp.
#include "data/bags/mcap.hpp"

#include <zstd.h>

#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/error_text.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid::bags {
namespace {

std::string readAll(const std::string& path) {
  std::string out;
  McapReader(path).read([&](const McapMessage& m) { out += std::string(m.data); });
  return out;
}

/// A minimal MCAP with one chunk holding a channel and a message, compressed as asked.
std::string chunkedFile(const std::string& compression, bool damage_crc) {
  const auto u16 = [](std::uint16_t v) { return std::string(reinterpret_cast<char*>(&v), 2); };
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<char*>(&v), 4); };
  const auto u64 = [](std::uint64_t v) { return std::string(reinterpret_cast<char*>(&v), 8); };
  const auto str = [&](const std::string& s) {
    return u32(static_cast<std::uint32_t>(s.size())) + s;
  };
  const auto record = [&](char op, const std::string& body) {
    return std::string(1, op) + u64(body.size()) + body;
  };
  const std::string inner =
      record(0x04, u16(1) + u16(0) + str("/joint_states") + str("cdr") + u32(0)) +
      record(0x05, u16(1) + u32(7) + u64(10) + u64(11) + "payload");
  std::string stored = inner;
  if (compression == "zstd") {
    stored.resize(ZSTD_compressBound(inner.size()));
    stored.resize(ZSTD_compress(stored.data(), stored.size(), inner.data(), inner.size(), 1));
  }
  std::uint32_t crc = crc32Of(inner);
  if (damage_crc) crc ^= 1u;
  const std::string chunk = u64(10) + u64(10) + u64(inner.size()) + u32(crc) + str(compression) +
                            u64(stored.size()) + stored;
  return std::string("\x89MCAP0\r\n", 8) + record(0x01, str("ros2") + str("test")) +
         record(0x06, chunk) + record(0x0F, u32(0)) + record(0x02, u64(0) + u64(0) + u32(0)) +
         std::string("\x89MCAP0\r\n", 8);
}

TEST(Mcap, ChunksDecompressAndTheirCrcIsChecked) {
  const std::string path = test::tempPath("chunk.mcap");
  for (const std::string compression : {"", "zstd"}) {
    writeFileAtomically(path, chunkedFile(compression, false));
    EXPECT_EQ(readAll(path), "payload") << compression;
    writeFileAtomically(path, chunkedFile(compression, true));
    EXPECT_NE(test::errorText([&] { readAll(path); }).find("CRC"), std::string::npos)
        << compression;
  }
  writeFileAtomically(path, chunkedFile("brotli", false));
  EXPECT_NE(test::errorText([&] { readAll(path); }).find("unknown compression 'brotli'"),
            std::string::npos);
  // Not MCAP at all, and a length field of 2^62.
  writeFileAtomically(path, "#ROSBAG V2.0\n");
  EXPECT_NE(test::errorText([&] { readAll(path); }).find("not an MCAP file"), std::string::npos);
  std::string huge = chunkedFile("", false);
  const std::uint64_t big = std::uint64_t{1} << 62;
  std::memcpy(huge.data() + 8 + 1, &big, 8);  // the Header record's length
  writeFileAtomically(path, huge);
  EXPECT_NE(test::errorText([&] { readAll(path); }).find("at byte 8"), std::string::npos);
}

// A file cut anywhere is refused with the file and a byte offset, never read past its end.
TEST(Mcap, EveryTruncationIsRefusedWithTheFileAndOffset) {
  const std::string whole = chunkedFile("zstd", false);
  const std::string path = test::tempPath("cut.mcap");
  int refused = 0;
  for (std::size_t length = 0; length < whole.size(); ++length) {
    writeFileAtomically(path, whole.substr(0, length));
    const std::string message = test::errorText([&] { readAll(path); });
    // A cut after the Data End record loses only the footer: the messages are all there.
    if (message.empty()) {
      EXPECT_GE(length, whole.size() - 8 - 29) << "a cut before Data End was read";
      continue;
    }
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("at byte"), std::string::npos) << message;
    ++refused;
  }
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace dynid::bags
