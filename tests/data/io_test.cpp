#include "data/io.hpp"
#include "core/format.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <thread>
#include <vector>

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

TEST(Io, AFifoIsWrittenThroughNotReplaced) {
  // A FIFO in the test's own directory (never a system device: a regression would replace it).
  const std::string fifo = test::tempPath("out.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = readFile(fifo); });
  writeFileAtomically(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  struct stat after {};
  ASSERT_EQ(::stat(fifo.c_str(), &after), 0);
  EXPECT_TRUE(S_ISFIFO(after.st_mode));
  std::filesystem::remove(fifo);
}

TEST(Io, ADirectoryTargetIsRefusedAndLeftAlone) {
  const std::string dir = test::tempPath("a-directory");
  std::filesystem::create_directories(dir);
  try {
    writeFileAtomically(dir, "x");
    FAIL() << "expected Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file (a directory)"), std::string::npos);
  }
  EXPECT_TRUE(std::filesystem::is_directory(dir));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(Io, ReadFileRefusesDirectoriesAndCapsStreams) {
  EXPECT_THROW(readFile(std::string(DYNID_TEST_TMP)), Error);
  // /dev/zero never ends: a stream is read up to its cap, then refused naming the file.
  try {
    readFile("/dev/zero", 1e6);
    ADD_FAILURE() << "an endless stream was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'/dev/zero' holds more than 1 MB"), std::string::npos)
        << e.what();
  }
  const std::string path = test::tempPath("capped.txt");
  writeFileAtomically(path, std::string(2000, 'x'));
  EXPECT_EQ(readFile(path, 2000).size(), 2000u);
  EXPECT_THROW(readFile(path, 1999), InputError);  // a regular file over its cap
}

TEST(Io, ACommitRemovesTheTemporariesOfDeadWriters) {
  const std::string path = test::tempPath("target.txt");
  // A pid that existed and has ended (a child, reaped), and this process's own.
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string stale = path + ".tmp." + std::to_string(dead);
  const std::string alive = path + ".tmp." + std::to_string(::getppid());  // our parent lives
  writeFileAtomically(stale, "left by a SIGKILL");
  writeFileAtomically(alive, "another writer at work");
  writeFileAtomically(path, "new");
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_TRUE(std::filesystem::exists(alive));
  EXPECT_EQ(readFile(path), "new");
}

TEST(Io, APlantedLinkOrFileAtTheTemporarysNameIsNeverWrittenThrough) {
  // A link planted where the temporary used to be (<path>.tmp.<pid>, predictable) or at a staged
  // name: the temporary is created exclusively and never through a link, so the victim stays.
  const std::string victim = test::tempPath("victim.txt");
  writeFileAtomically(victim, "precious");
  const std::string path = test::tempPath("planted.txt");
  const std::string old_name = path + ".tmp." + std::to_string(::getpid());
  ASSERT_EQ(::symlink(victim.c_str(), old_name.c_str()), 0);
  writeFileAtomically(path, "output");
  EXPECT_EQ(readFile(path), "output");
  EXPECT_EQ(readFile(victim), "precious");
  EXPECT_TRUE(std::filesystem::is_symlink(old_name));  // a live process's name: left alone
  std::filesystem::remove(old_name);
}

TEST(Io, ALinkAtAnOutputIsReplacedNotFollowed) {
  const std::string victim = test::tempPath("victim2.txt");
  writeFileAtomically(victim, "precious");
  for (const ExistingTarget existing : {ExistingTarget::kFollow, ExistingTarget::kReplace}) {
    const std::string link = test::tempPath("link.txt");
    std::filesystem::remove(link);
    ASSERT_EQ(::symlink(victim.c_str(), link.c_str()), 0);
    AtomicWriter out(link, existing);
    out.write("new");
    out.commit();
    EXPECT_FALSE(std::filesystem::is_symlink(link));
    EXPECT_EQ(readFile(link), "new");
    EXPECT_EQ(readFile(victim), "precious");
  }
  // With kReplace (names dynid chose), a link to a stream is replaced too, never written through.
  const std::string fifo = test::tempPath("victim.fifo"), link = test::tempPath("to-fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_EQ(::symlink(fifo.c_str(), link.c_str()), 0);
  writeFileAtomically(link, "x", ExistingTarget::kReplace);
  EXPECT_EQ(readFile(link), "x");
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
}

TEST(Io, WithAnInputGuardACommandsInputIsNeverReplaced) {
  const std::string input = test::tempPath("input.txt"), alias = test::tempPath("alias.txt");
  writeFileAtomically(input, "read me");
  std::filesystem::remove(alias);
  std::filesystem::create_hard_link(input, alias);
  {
    const InputFileGuard guard;
    EXPECT_EQ(readFile(input), "read me");
    EXPECT_TRUE(isInputFile(input));
    EXPECT_TRUE(isInputFile(alias));  // the same file by another name
    for (const std::string& target : {input, alias}) {
      try {
        writeFileAtomically(target, "overwritten");
        ADD_FAILURE() << target;
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is an input of this command"), std::string::npos);
      }
    }
    writeFileAtomically(input, "a checkpoint", ExistingTarget::kUpdate);  // read to be rewritten
    EXPECT_EQ(readFile(input), "a checkpoint");
  }
  EXPECT_EQ(readFile(alias), "read me");  // the rewrite replaced the name, not the file
  writeFileAtomically(alias, "no guard, no refusal");
  EXPECT_FALSE(isInputFile(alias));
}

int deferred_signals = 0, acted_signals = 0;
extern "C" void onTestSignal(int signal) {
  if (deferSignalWhilePublishing(signal))
    ++deferred_signals;
  else
    ++acted_signals;
}

TEST(Io, ASignalDuringAPublishWindowWaitsForItsEnd) {
  void (*previous)(int) = std::signal(SIGUSR1, onTestSignal);
  deferred_signals = acted_signals = 0;
  {
    const PublishWindow outer;
    {
      const PublishWindow inner;  // nested: the outermost decides
      std::raise(SIGUSR1);
    }
    std::raise(SIGUSR1);  // one is already waiting
    EXPECT_EQ(deferred_signals, 2);
    EXPECT_EQ(acted_signals, 0);
  }
  EXPECT_EQ(acted_signals, 1);  // raised again once the window closed
  std::raise(SIGUSR1);
  EXPECT_EQ(acted_signals, 2);  // no window: acted on at once
  std::signal(SIGUSR1, previous);
}

TEST(Io, FormatDoubleRoundTrips) {
  for (double x : {0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 0.0}) {
    const std::string s = formatNumber(x);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), x) << s;
  }
  EXPECT_EQ(formatNumber(0.1), "0.1");
  EXPECT_EQ(formatNumber(std::numeric_limits<double>::infinity()), "inf");
}

TEST(Io, LineReaderReturnsEveryLineOfAnyLength) {
  const std::string path = test::tempPath("lines.txt");
  const std::string long_line(100000, 'x');  // longer than a small file's first block
  writeFileAtomically(path,
                      "\xEF\xBB\xBF"
                      "first\r\n\n" +
                          long_line + "\nlast");
  LineReader reader(path);
  std::vector<std::string> lines;
  std::string_view line;
  while (reader.next(line)) lines.emplace_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "first\r");  // the byte-order mark dropped, a '\r' kept
  EXPECT_EQ(lines[1], "");
  EXPECT_EQ(lines[2], long_line);
  EXPECT_EQ(lines[3], "last");  // no final newline
  EXPECT_EQ(reader.lineNumber(), 4);
  EXPECT_FALSE(reader.next(line));
  EXPECT_THROW(LineReader(test::tempPath("no-such-file")), Error);
  EXPECT_THROW(LineReader(std::filesystem::temp_directory_path().string()), Error);
}

}  // namespace
}  // namespace dynid

TEST(Io, PrintableUtf8AcceptsTextAndRefusesBadBytesAndControls) {
  using namespace std::string_literals;
  for (const std::string& good :
       {"link3"s, ""s, "Gelenk_Ärmel"s, "\u8155"s, "\U0001F916"s, "tab-free name with spaces"s})
    EXPECT_TRUE(dynid::isPrintableUtf8(good)) << good;
  for (const std::string& bad : {"puma\xe4"s,          // Latin-1 ä
                                 "\xc3"s,              // truncated two-byte sequence
                                 "\xc0\xaf"s,          // overlong '/'
                                 "\xed\xa0\x80"s,      // a UTF-16 surrogate
                                 "\xf4\x90\x80\x80"s,  // past U+10FFFF
                                 "\x80"s,              // a continuation byte alone
                                 "a\tb"s, "a\nb"s, "a\x7f"s, "a\0b"s})
    EXPECT_FALSE(dynid::isPrintableUtf8(bad)) << bad;
}

namespace dynid {
namespace {

/// The names in `dir` that start with `prefix`.
std::vector<std::string> namesStartingWith(const std::string& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  return out;
}

TEST(Io, NoNameExistsWhileAFileIsWrittenOnlyFromItsStage) {
  // A SIGKILL while writing (a search's checkpoint, every round) must leave nothing behind: the
  // temporary is unnamed (O_TMPFILE) until its content is whole and synced.
  const std::string dir = test::tempPath("unnamed_dir");
  std::filesystem::create_directories(dir);
  const int probe = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (probe < 0 || ::access("/proc/self/fd", X_OK) != 0)
    GTEST_SKIP() << "this file system has no O_TMPFILE (or no /proc): named temporaries there";
  ::close(probe);
  const std::string path = dir + "/checkpoint.json";
  {
    AtomicWriter out(path);
    out.write(std::string(3 << 20, 'x'));  // past the buffer: written to the file
    EXPECT_EQ(namesStartingWith(dir, "checkpoint.json"), std::vector<std::string>{});
    out.stage();
    const std::vector<std::string> staged = namesStartingWith(dir, "checkpoint.json.tmp.");
    ASSERT_EQ(staged.size(), 1u);  // named once whole, exclusively, then renamed
    out.commit();
  }
  EXPECT_EQ(namesStartingWith(dir, "checkpoint.json"), std::vector<std::string>{"checkpoint.json"});
  EXPECT_EQ(readFile(path).size(), std::size_t{3} << 20);
  // Abandoned before its stage (an exception on the way): nothing was ever named.
  {
    AtomicWriter out(path);
    out.write("partial");
  }
  EXPECT_EQ(namesStartingWith(dir, "checkpoint.json"), std::vector<std::string>{"checkpoint.json"});
  EXPECT_EQ(readFile(path).size(), std::size_t{3} << 20);
}

}  // namespace
}  // namespace dynid
