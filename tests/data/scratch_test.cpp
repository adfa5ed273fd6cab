#include "data/scratch.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <numeric>
#include <vector>

#include "core/errors.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// Columns written in pieces, out of order and from several places, read back exactly; the file
// has no name in the directory (nothing to leave behind, nothing for a link to redirect).
TEST(ScratchColumns, WritesReadBackAndLeaveNoFileBehind) {
  const std::string dir = test::tempPath("scratch");
  std::filesystem::create_directories(dir);
  {
    ScratchColumns s(dir, 3, 1000);
    std::vector<double> v(1000);
    std::iota(v.begin(), v.end(), 0.5);
    s.write(2, 600, v.data() + 600, 400);
    s.write(0, 0, v.data(), 1000);
    s.write(2, 0, v.data(), 600);
    std::vector<double> back(1000, -1.0);
    s.read(2, 0, back.data(), 1000);
    EXPECT_EQ(back, v);
    s.read(0, 250, back.data(), 10);
    EXPECT_EQ(back[0], 250.5);
    EXPECT_EQ(back[9], 259.5);
    s.read(1, 0, back.data(), 5);  // never written: zeros
    EXPECT_EQ(back[0], 0.0);
    EXPECT_EQ(back[4], 0.0);
    EXPECT_THROW(s.read(2, 990, back.data(), 11), Error);  // past the rows
    EXPECT_THROW(s.write(3, 0, v.data(), 1), Error);       // no such column
    EXPECT_TRUE(std::filesystem::is_empty(dir));
  }
  {
    // Appended across blocks without knowing the count: a column's rows in any block read back.
    const std::int64_t rows = 2 * ScratchColumns::kBlockRows + 123;
    ScratchColumns s(dir, 2);
    std::vector<double> v(static_cast<std::size_t>(rows));
    std::iota(v.begin(), v.end(), -7.25);
    for (std::int64_t first = 0; first < rows; first += 1000) {
      const std::int64_t count = std::min<std::int64_t>(1000, rows - first);
      s.write(1, first, v.data() + first, count);
      s.write(0, first, v.data() + first, count);
    }
    EXPECT_EQ(s.rows(), rows);
    std::vector<double> back(v.size());
    s.read(1, 0, back.data(), rows);
    EXPECT_EQ(back, v);
    s.read(0, ScratchColumns::kBlockRows - 3, back.data(), 10);  // across a block's edge
    EXPECT_EQ(back[0], v[ScratchColumns::kBlockRows - 3]);
    EXPECT_EQ(back[9], v[ScratchColumns::kBlockRows + 6]);
    EXPECT_TRUE(std::filesystem::is_empty(dir));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

// A write the file system refuses (here the file-size limit, EFBIG; a full disk alike) is an
// Error naming the directory and the reason, never a short write taken as done.
TEST(ScratchColumns, AWriteThatFailsNamesTheDirectoryAndWhy) {
  const std::string dir = test::tempPath("scratch_fsize");
  std::filesystem::create_directories(dir);
  rlimit previous{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &previous), 0);
  void (*const previous_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = previous;
  limit.rlim_cur = 1 << 20;  // 1 MB: the second column's first block lies past it
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message;
  {
    ScratchColumns s(dir, 4);
    const std::vector<double> v(1000, 2.5);
    try {
      s.write(0, 0, v.data(), 1000);  // within the limit
      s.write(3, 0, v.data(), 1000);  // at 1.5 MB
    } catch (const Error& e) {
      message = e.what();
    }
  }
  setrlimit(RLIMIT_FSIZE, &previous);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_NE(message.find(dir), std::string::npos) << message;
  EXPECT_NE(message.find("too large"), std::string::npos) << message;
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(ScratchColumns, ADirectoryThatIsNotThereIsNamed) {
  const std::string dir = test::tempPath("no-such-dir");
  try {
    ScratchColumns s(dir, 1, 10);
    FAIL() << "made a scratch file in a directory that does not exist";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir), std::string::npos) << e.what();
  }
}

TEST(ScratchColumns, TheNearestExistingDirectoryIsWhereTheOutputWillBe) {
  const std::string dir = test::tempPath("nearest");
  std::filesystem::create_directories(dir);
  EXPECT_EQ(nearestExistingDirectory(dir), dir);
  EXPECT_EQ(nearestExistingDirectory(dir + "/a/b/out"), dir);
  EXPECT_EQ(nearestExistingDirectory("no-such-dir-7/out"), ".");
}

}  // namespace
}  // namespace dynid
