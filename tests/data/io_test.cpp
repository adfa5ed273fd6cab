#include "data/io.hpp"

#include <cstdlib>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Io, AtomicWriteReplacesWholeFileAndLeavesNoTemporary) {
  const std::string path = test::tempPath("atomic.txt");
  writeFileAtomically(path, "first");
  writeFileAtomically(path, "second version");
  EXPECT_EQ(readFile(path), "second version");
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    EXPECT_EQ(entry.path().string().find(path + ".tmp"), std::string::npos);
  EXPECT_THROW(writeFileAtomically("/nonexistent-dir/x.txt", "x"), Error);
  EXPECT_THROW(readFile("/nonexistent-dir/x.txt"), Error);
}

TEST(Io, FormatDoubleRoundTrips) {
  for (double x : {0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 0.0}) {
    const std::string s = formatDouble(x);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), x) << s;
  }
  EXPECT_EQ(formatDouble(0.1), "0.1");
  EXPECT_EQ(formatDouble(std::numeric_limits<double>::infinity()), "inf");
}

}  // namespace
}  // namespace dynid
