// The MCAP project's conformance files (tests/data/bags/fixtures/mcap_conformance/: all 416
// variants, byte-identical to the published ones, tools/mcap/make_conformance.sh): every file
// reads, and gives exactly the messages the project's expected output lists (channel, topic,
// log and publish time, sequence, bytes) in order, whatever its chunks, indexes, padding and
// summary.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/bags/mcap.hpp"
#include "tests/common/fixtures.hpp"

namespace dynid::bags {
namespace {

namespace fs = std::filesystem;
const fs::path kConformance = test::bagFixtures() / "mcap_conformance";

std::string hex(std::string_view bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (const char c : bytes) {
    out += kDigits[static_cast<unsigned char>(c) >> 4];
    out += kDigits[static_cast<unsigned char>(c) & 15];
  }
  return out.empty() ? "-" : out;
}

TEST(McapConformance, EveryPublishedFileGivesItsExpectedMessages) {
  std::ifstream expected(kConformance / "expected.txt");
  ASSERT_TRUE(expected) << "tests/data/bags/fixtures/mcap_conformance/expected.txt";
  int files = 0, messages = 0;
  std::string line;
  while (std::getline(expected, line)) {
    std::istringstream head(line);
    std::string word, name;
    int count = 0;
    ASSERT_TRUE(head >> word >> name >> count && word == "file") << line;
    std::vector<std::string> want(static_cast<std::size_t>(count));
    for (std::string& m : want) ASSERT_TRUE(std::getline(expected, m));
    SCOPED_TRACE(name);
    std::vector<std::string> got;
    try {
      McapReader reader((kConformance / name).string());
      reader.read([&](const McapMessage& m) {
        const auto channel = reader.channels().find(m.channel_id);
        ASSERT_NE(channel, reader.channels().end());
        got.push_back(std::to_string(m.channel_id) + " " + channel->second.topic + " " +
                      std::to_string(m.log_time) + " " + std::to_string(m.publish_time) + " " +
                      std::to_string(m.sequence) + " " + hex(m.data));
      });
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
    }
    EXPECT_EQ(got, want);
    ++files;
    messages += count;
  }
  EXPECT_EQ(files, 416);  // every variant the generator makes
  EXPECT_GT(messages, 1000);
}

}  // namespace
}  // namespace dynid::bags
