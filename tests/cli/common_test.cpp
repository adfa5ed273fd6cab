// What every command shares (cli/common.cpp): option values checked and named, robot files that
// fail to load named with their line.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/option_ranges.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, UsageErrorsNameTheOption) {
  Result r = run("dynamics --robot puma560 --q 1,2");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--q has 2 entries, the robot has 6 joints")) << r.err;
  r = run("dynamics --robot puma560 --dq 1,x,0,0,0,0");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--dq: entry 2 'x' is not a finite number")) << r.err;
  r = run("dynamics --robot puma560 --ddq 0,0,0,0,0,0 --tau 0,0,0,0,0,0");
  EXPECT_EQ(r.code, 2);
  r = run("dynamics --q 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--robot")) << r.err;
  r = run("simulate --robot puma560 --out x.csv --integrator rk45");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "unknown integrator 'rk45'")) << r.err;
  r = run("model export --robot puma560 --format sdf --out x");
  EXPECT_EQ(r.code, 2);
  // An empty value (an unset shell variable) is a usage error naming the option.
  r = run("model export --robot puma560 --format json --out ''");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--out is empty")) << r.err;
}
TEST(Cli, HelpShowsEachNumericOptionsRangeFromTheOneTable) {
  // The range printed is the table's (core/option_ranges.hpp), the one the parser checks.
  const Result excite = run("excite --help");
  EXPECT_EQ(excite.code, 0);
  const OptionRule* harmonics = findOptionRule("excite", "harmonics");
  ASSERT_NE(harmonics, nullptr);
  const std::string harmonics_help =
      std::string(harmonics->help).append(" (").append(optionRangeText(*harmonics)) + ")";
  EXPECT_EQ(std::string(harmonics->help), "harmonics per joint");
  EXPECT_TRUE(contains(excite.out, harmonics_help)) << excite.out;
  EXPECT_TRUE(contains(excite.out, "-h [ --help ]")) << excite.out;
  // A command-specific rule wins over the general one: study's segments start at 1.
  const Result study = run("study --help");
  const OptionRule* segments = findOptionRule("study", "segments");
  ASSERT_NE(segments, nullptr);
  EXPECT_EQ(optionRangeText(*segments).rfind(">= 1", 0), 0u);
  // Appended, not concatenated: GCC 12 warns (-Wrestrict, falsely) on "(" + std::string&&.
  const std::string segments_help = std::string("(").append(optionRangeText(*segments)) + ")";
  EXPECT_TRUE(contains(study.out, segments_help)) << study.out;
  // And the parser refuses what the help rules out, in the same words.
  const Result refused = run("excite --robot puma560 --harmonics 51 --out x");
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(contains(refused.err, "--harmonics must be " + optionRangeText(*harmonics)))
      << refused.err;
}

/// The help with every run of whitespace (Boost's wrapping) made one space.
std::string collapsed(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool space = c == ' ' || c == '\n';
    if (!space || (!out.empty() && out.back() != ' ')) out += space ? ' ' : c;
  }
  return out;
}

TEST(Cli, EveryNumericOptionsHelpIsTheTablesWithItsRange) {
  // The commands declare numeric options without words; --help takes them from the table.
  for (const char* command : {"simulate", "identifiability", "identify", "search", "refine",
                              "prepare", "excite", "study", "batch", "demo"}) {
    const Result r = run(std::string(command) + " --help");
    ASSERT_EQ(r.code, 0) << command;
    const std::string text = collapsed(r.out);
    int numeric = 0;
    std::size_t at = 0;
    while ((at = r.out.find("\n  --", at)) != std::string::npos) {
      at += 5;
      const std::string name = r.out.substr(at, r.out.find_first_of(" \n", at) - at);
      const OptionRule* rule = findOptionRule(command, name);
      if (rule == nullptr) continue;
      ++numeric;
      const std::string expected =
          std::string(rule->help).append(" (").append(optionRangeText(*rule)).append(")");
      EXPECT_TRUE(contains(text, expected)) << command << " --" << name << "\n" << r.out;
    }
    EXPECT_GT(numeric, 0) << command;
  }
  // Defaults read as they were written: 0.05, not 0.050000000000000003.
  EXPECT_TRUE(contains(run("search --help").out, "--horizon arg (=0.05)"));
}

/// `text` as one shell word (the CLI tests run dynid through the shell).
std::string shellWord(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

TEST(Cli, HostileNamesInARobotFileItsPathAndTmpdirRunNoCommandAndKeepEveryFigure) {
  // A downloaded URDF's joint and link names, the robot file's path (a figure title of predict) and
  // TMPDIR reach gnuplot as text only: none runs a command, and every figure is still drawn.
  namespace fs = std::filesystem;
  if (std::system("gnuplot --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  const std::string marker = test::tempPath("hostile_marker");
  std::remove(marker.c_str());
  const std::string dir = test::tempPath("it's \"hostile\" `dir`");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string urdf = dir + "/o'brien.urdf";
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + shellWord(urdf)).code, 0);
  std::string text = readFile(urdf);
  // In XML attribute form (&quot; is "); control characters are refused when the file is read.
  const std::string names[] = {"'.system('touch " + marker + "').'",
                               "x&quot;.system(&quot;touch " + marker + "&quot;).&quot;",
                               "!touch " + marker + " #",
                               "`touch " + marker + "`",
                               "@M {x}_^ $(touch " + marker + ")",
                               "o'brien; touch " + marker};
  for (int j = 0; j < 6; ++j)
    for (const std::string kind : {"joint", "link"}) {  // link j + 1: the same, suffixed
      const std::string from = "\"" + kind + std::to_string(j + 1) + "\"";
      const std::string to = kind == "joint" ? names[j] : names[j] + " " + kind;
      for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at))
        text.replace(at, from.size(), "\"" + to + "\"");
    }
  { std::ofstream(urdf) << text; }
  const std::string tmpdir = dir + "/tmp'dir";
  fs::create_directories(tmpdir);
  const char* previous = std::getenv("TMPDIR");
  const std::string saved = previous != nullptr ? previous : "";
  ::setenv("TMPDIR", tmpdir.c_str(), 1);

  const std::string robot = "--robot " + shellWord(urdf);
  const Result excite =
      run("excite " + robot + " --segments 10 --starts 1 --evaluations 20 --out " +
          shellWord(dir + "/excite"));
  const Result simulate =
      run("simulate " + robot + " --duration 1 --out " + shellWord(dir + "/data.csv"));
  const Result identify = run("identify " + robot + " --data " + shellWord(dir + "/data.csv") +
                              " --out " + shellWord(dir + "/identify"));
  const Result predict =
      run("predict --estimate " + shellWord(dir + "/identify/estimate.json") + " --data " +
          shellWord(dir + "/data.csv") + " --out " + shellWord(dir + "/predict"));
  if (previous != nullptr)
    ::setenv("TMPDIR", saved.c_str(), 1);
  else
    ::unsetenv("TMPDIR");
  for (const Result* r : {&excite, &simulate, &identify, &predict}) {
    EXPECT_EQ(r->code, 0) << r->err;
    EXPECT_FALSE(contains(r->out + r->err, "gnuplot")) << r->out << r->err;  // no figure lost
  }
  EXPECT_NE(::access(marker.c_str(), F_OK), 0) << "a command ran";
  int svgs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.path().extension() == ".svg") ++svgs;
  EXPECT_GE(svgs, 3);
  EXPECT_TRUE(fs::is_empty(tmpdir));  // and nothing was left in TMPDIR
}

TEST(Cli, DataErrorsNameTheFile) {
  const Result r = run("dynamics --robot /nonexistent/arm.urdf");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "/nonexistent/arm.urdf")) << r.err;
  const std::string bad = test::tempPath("bad.urdf");
  std::ofstream(bad)
      << "<robot name='x'><link name='a'/><link name='b'><inertial><mass value='-1'/>"
         "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link>"
         "<joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
         "<limit lower='-1' upper='1' effort='1' velocity='1'/></joint></robot>";
  const Result urdf = run("model show --robot " + bad);
  EXPECT_EQ(urdf.code, 1);
  EXPECT_TRUE(contains(urdf.err, bad + ":1: link 'b': negative mass")) << urdf.err;
  // A massless moving link: loads with a warning, and its dynamics are reported singular.
  const std::string massless = test::tempPath("massless.urdf");
  std::ofstream(massless) << "<robot name='x'><link name='a'/><link name='b'/>"
                             "<joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
                             "</joint></robot>";
  const Result singular = run("dynamics --robot " + massless + " --tau 1");
  EXPECT_EQ(singular.code, 1);
  EXPECT_TRUE(contains(singular.err, "warning: " + massless + ": link 'b' has no <inertial>"))
      << singular.err;
  EXPECT_TRUE(contains(singular.err, "singular")) << singular.err;
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

TEST(Cli, EveryLongCommandStopsSoonAfterCtrlCWithExit130AndItsBestResultWritten) {
  const std::string dir = test::tempPath("ctrl_c");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(test::run("simulate --robot puma560 --drives --duration 8 --noise-tau 0.2 --seed 1 "
                      "--out " +
                      dir + "/train.csv")
                .code,
            0);
  ASSERT_EQ(test::run("simulate --robot puma560 --drives --duration 2 --noise-tau 0.2 --seed 2 "
                      "--out " +
                      dir + "/test.csv")
                .code,
            0);
  ASSERT_EQ(test::run("identify --method pc --robot puma560 --drives --data " + dir +
                      "/train.csv --out " + dir + "/pc")
                .code,
            0);
  const std::string data = " --robot puma560 --drives --data " + dir + "/train.csv";
  struct Case {
    std::string args, written;
    double signal_at = 2.0;  // s: every command is then in its long loop
  };
  const std::vector<Case> cases = {
      {"search --method ga --perturb 0.3 --budget-seconds 60" + data, "search.json"},
      {"refine --from " + dir + "/pc/estimate.json --budget-seconds 60" + data, "refine.json"},
      {"excite --robot panda", "excitation.json", 5.0},  // a start within the limits by then
      {"identify --method combined --combined-seconds 60" + data, "estimate.json", 0.5},
      {"study --validate " + dir + "/test.csv" + data, "study.json"},
      {"demo", "summary.json"},
      {"batch " + std::string(DYNID_SOURCE_DIR) + "/examples/noise_study.json --jobs 2",
       "results.json"}};
  for (const Case& c : cases) {
    const std::string out = dir + "/out";
    std::filesystem::remove_all(out);
    // SIGINT `signal_at` s in, then the time until it exits.
    // (cd first, on its own: "cd D && dynid ... &" would put the pair in a subshell that
    // ignores SIGINT, as background jobs of a script do, and $! would be that subshell.)
    const std::string script = "cd " + dir + " || exit 1; " + DYNID_BIN + " " + c.args + " --out " +
                               out + " >stdout.txt 2>stderr.txt & pid=$!; sleep " +
                               std::to_string(c.signal_at) +
                               "; "
                               "t0=$(date +%s.%N); kill -INT $pid; wait $pid; code=$?; "
                               "t1=$(date +%s.%N); echo \"$code $(echo \"$t1 - $t0\" | bc)\" "
                               ">" +
                               dir + "/stopped.txt";
    ASSERT_EQ(std::system(("bash -c '" + script + "'").c_str()), 0) << c.args;
    int code = -1;
    double seconds = -1.0;
    ASSERT_EQ(std::sscanf(readFile(dir + "/stopped.txt").c_str(), "%d %lf", &code, &seconds), 2);
    const std::string err = readFile(dir + "/stderr.txt");
    EXPECT_EQ(code, 130) << c.args << "\n" << err;
    EXPECT_TRUE(contains(err, "interrupted (Ctrl-C)")) << c.args << "\n" << err;
    EXPECT_TRUE(std::filesystem::exists(out + "/" + c.written)) << c.args;
    // Stopped within a second of the signal when run alone (0.03-0.7 s measured); 1.5 s here,
    // as ctest runs two tests at once on two cores.
    EXPECT_LT(seconds, 1.5) << c.args;
    std::printf("%s: exit %d, %.2f s after SIGINT\n", c.args.substr(0, c.args.find(' ')).c_str(),
                code, seconds);
  }
}

// The library names request fields (`time_column`, `torque_constants`); the CLI's messages name
// its flags (--time, --torque-constants), and a file name in backquotes stays as it is.
TEST(Cli, LibraryMessagesNameTheFlags) {
  const std::string log = test::tempPath("`hostile` log.csv");
  writeFileAtomically(log, "stamp,pos1,eff1\n0,0,0\n0.001,0,0\n0.002,0,0\n");
  Result r = run("prepare --log '" + log + "' --time nothing --q 'pos*' --tau 'eff*' --out " +
                 test::tempPath("flags_out"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "--time")) << r.err;
  EXPECT_FALSE(contains(r.err, "`time_column`")) << r.err;
  EXPECT_TRUE(contains(r.err, "`hostile` log.csv")) << r.err;  // the user's name, untouched
  r = run("prepare --log '" + log + "' --q 'pos*' --current 'eff*' --torque-constants 1,2 --out " +
          test::tempPath("flags_out"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "--torque-constants has 2 values")) << r.err;
}

}  // namespace
}  // namespace dynid
