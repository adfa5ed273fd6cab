// Output sets (reports/output.hpp): published whole, never through a link, the same command's
// earlier files that this run did not write removed, nothing else touched.
#include "reports/output.hpp"

#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;

/// The names in `dir`.
std::set<std::string> listing(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

TEST(OutputSet, NothingIsInPlaceBeforePublishAndNothingIsLeftWithoutIt) {
  const std::string dir = test::tempPath("set_unpublished");
  fs::remove_all(dir);
  writeReportFiles(dir, {{"a.json", "old a"}, {"b.csv", "old b"}});
  {
    OutputSet set(dir);
    set.add("a.json", "new a");
    set.stream("b.csv").write("new b");
    EXPECT_EQ(readFile(dir + "/a.json"), "old a");  // staged, not in place
    // destroyed unpublished: an exception or an interrupted run
  }
  EXPECT_EQ(readFile(dir + "/a.json"), "old a");
  EXPECT_EQ(readFile(dir + "/b.csv"), "old b");
  EXPECT_EQ(listing(dir), (std::set<std::string>{"a.json", "b.csv", ".dynid-outputs-dynid"}));
}

TEST(OutputSet, ARerunRemovesOnlyItsOwnEarlierFilesThatItDidNotWrite) {
  const std::string dir = test::tempPath("set_rerun");
  fs::remove_all(dir);
  fs::create_directories(dir);
  writeFileAtomically(dir + "/notes.txt", "the user's");
  OutputSet::setCommand("prepare");
  writeReportFiles(dir, {{"train.csv", "1"}, {"validate.csv", "2"}, {"prepare.json", "3"}});
  OutputSet::setCommand("identify");
  writeReportFiles(dir, {{"estimate.json", "4"}});
  OutputSet::setCommand("prepare");
  writeReportFiles(dir, {{"train.csv", "5"}, {"prepare.json", "6"}});  // no hold-out this time
  OutputSet::setCommand("dynid");
  EXPECT_EQ(listing(dir),
            (std::set<std::string>{"notes.txt", "train.csv", "prepare.json", "estimate.json",
                                   ".dynid-outputs-prepare", ".dynid-outputs-identify"}));
  EXPECT_EQ(readFile(dir + "/train.csv"), "5");
  EXPECT_EQ(readFile(dir + "/.dynid-outputs-prepare"),
            "dynid output set\ntrain.csv\nprepare.json\n");
}

TEST(OutputSet, ARecordNamingPathsOrTheCommandsInputsRemovesNothingOutsideTheSet) {
  const std::string dir = test::tempPath("set_hostile_record");
  fs::remove_all(dir);
  fs::create_directories(dir + "/sub");
  const std::string outside = test::tempPath("outside.txt");
  writeFileAtomically(outside, "keep");
  writeFileAtomically(dir + "/sub/x", "keep");
  writeFileAtomically(dir + "/input.csv", "keep");
  writeFileAtomically(dir + "/.dynid-outputs-dynid", "dynid output set\n../outside.txt\n" +
                                                         outside + "\nsub/x\n..\n.\ninput.csv\n");
  {
    const InputFileGuard guard;
    ASSERT_EQ(readFile(dir + "/input.csv"), "keep");
    writeReportFiles(dir, {{"out.json", "{}"}});
  }
  EXPECT_EQ(readFile(outside), "keep");
  EXPECT_EQ(readFile(dir + "/sub/x"), "keep");
  EXPECT_EQ(readFile(dir + "/input.csv"), "keep");  // this command's input: never removed
}

TEST(OutputSet, ALinkPlantedAtAnOutputIsReplacedAndItsTargetKept) {
  const std::string dir = test::tempPath("set_links");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string victim = test::tempPath("set_victim.txt");
  writeFileAtomically(victim, "precious");
  ASSERT_EQ(::symlink(victim.c_str(), (dir + "/report.md").c_str()), 0);
  ASSERT_EQ(::symlink(victim.c_str(), (dir + "/.dynid-outputs-dynid").c_str()), 0);
  writeReportFiles(dir, {{"report.md", "# report"}});
  EXPECT_EQ(readFile(victim), "precious");
  EXPECT_FALSE(fs::is_symlink(dir + "/report.md"));
  EXPECT_EQ(readFile(dir + "/report.md"), "# report");
  EXPECT_THROW(OutputSet(dir).add("../escape", "x"), Error);  // a set holds plain names only
}

}  // namespace
}  // namespace dynid
