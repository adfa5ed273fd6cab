// The command table (cli/command_table.cpp): help on every command, `dynid help`, no option
// guessing, --version, '-' as standard output, and the completion scripts and man pages generated
// from the commands' own option tables.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

// Every command and subcommand a user can type (batch run is the batch's internal worker).
const std::vector<std::string> kCommands = {
    "model show",      "model check", "model export", "dynamics",  "simulate", "prepare",
    "identifiability", "excite",      "identify",     "predict",   "payload",  "monitor",
    "audit",           "search",      "refine",       "demo",      "study",    "batch",
    "batch merge",     "completion",  "man",          "summarize", "fleet"};

TEST(CommandTable, DashHAndHelpAndHelpCommandOnEveryCommand) {
  for (const std::string& command : kCommands) {
    for (const std::string& form : {command + " -h", command + " --help", "help " + command}) {
      const Result r = run(form);
      EXPECT_EQ(r.code, 0) << form << ": " << r.err;
      EXPECT_TRUE(contains(r.out, "usage: dynid " + command.substr(0, command.find(' '))))
          << form << ": " << r.out;
      EXPECT_TRUE(contains(r.out, "--help")) << form;
    }
  }
  // The general usage lists every top-level command.
  const Result usage = run("help");
  EXPECT_EQ(usage.code, 0);
  for (const std::string& command : kCommands)
    EXPECT_TRUE(contains(usage.out, "  " + command.substr(0, command.find(' ')))) << command;
}

TEST(CommandTable, DashHAsAnOptionsValueIsTheValue) {
  // "--out -h" names a file called -h; it is not a request for help.
  const std::string dir = test::tempPath("dash_h_value");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const Result r = run("model export --robot puma560 --format json --out " + dir + "/-h");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/-h"));
}

TEST(CommandTable, AbbreviatedOptionsAreRefusedWithASuggestion) {
  // Boost.Program_options would take --meth for --method (and --out for --output if both
  // existed): a typo must not select an option silently.
  const Result r = run("identify --meth pc --robot puma560 --data x.csv --out y");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "unrecognised option '--meth'")) << r.err;
  EXPECT_TRUE(contains(r.err, "did you mean --method")) << r.err;
  const Result typo = run("simulate --robto puma560 --out x.csv");
  EXPECT_EQ(typo.code, 2);
  EXPECT_TRUE(contains(typo.err, "did you mean --robot")) << typo.err;
  const Result prefix = run("search --budget 5 --robot puma560 --data x --out y");
  EXPECT_EQ(prefix.code, 2);
  EXPECT_TRUE(contains(prefix.err, "--budget-seconds")) << prefix.err;
}

TEST(CommandTable, VersionNamesTheCommitEverywhere) {
  const Result top = run("--version");
  EXPECT_EQ(top.code, 0);
  EXPECT_TRUE(contains(top.out, "dynid " DYNID_VERSION_TEXT " (commit ")) << top.out;
  const Result sub = run("identify --version");
  EXPECT_EQ(sub.code, 0);
  EXPECT_EQ(sub.out, top.out);
}

TEST(CommandTable, DashIsStandardOutputForOneFileAndRefusedForADirectory) {
  const Result csv = run("simulate --robot puma560 --duration 0.1 --out -");
  ASSERT_EQ(csv.code, 0) << csv.err;
  EXPECT_EQ(csv.out.rfind("t,q1,", 0), 0u) << csv.out.substr(0, 80);
  EXPECT_TRUE(contains(csv.err, "wrote standard output")) << csv.err;  // the summary moves
  EXPECT_FALSE(std::filesystem::exists("-"));
  const Result truth =
      run("simulate --robot puma560 --duration 0.1 --disturbance joint=1,torque=1,at=0,for=0.05 "
          "--out -");
  // Piped to a monitor: the samples on standard output, the ground truth not written (said so).
  EXPECT_EQ(truth.code, 0) << truth.err;
  EXPECT_EQ(truth.out.rfind("t,q1,", 0), 0u) << truth.out.substr(0, 80);
  EXPECT_TRUE(contains(truth.err, "not written (--truth-out FILE writes them)")) << truth.err;
  const Result model = run("model export --robot puma560 --format urdf --out -");
  EXPECT_EQ(model.code, 0);
  EXPECT_TRUE(contains(model.out, "<robot")) << model.out.substr(0, 80);
  for (const char* command : {"identify --robot puma560 --data x.csv --out -", "demo --out -",
                              "predict --robot puma560 --data x.csv --out -"}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_TRUE(contains(r.err, "names a directory")) << command << ": " << r.err;
  }
  const Result urdf = run("identify --robot " + std::string(DYNID_SOURCE_DIR) +
                          "/tests/fuzz/corpus/urdf/panda.urdf --data x.csv --out y --write-urdf -");
  EXPECT_EQ(urdf.code, 2);
  EXPECT_TRUE(contains(urdf.err, "writes two files")) << urdf.err;
}

/// Runs bash completion for `line` (the word being completed last) and returns COMPREPLY.
std::string complete(const std::string& script, const std::string& line) {
  const std::string out = test::tempPath("completion_out");
  const std::string command = "bash -c 'source " + script + "; COMP_WORDS=(" + line +
                              "); COMP_CWORD=$(( ${#COMP_WORDS[@]} - 1 )); _dynid; "
                              "echo \"${COMPREPLY[*]}\"' >" +
                              out;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return readFile(out);
}

TEST(CommandTable, BashCompletionKnowsEveryCommandAndOption) {
  const std::string script = test::tempPath("dynid.bash");
  ASSERT_EQ(run("completion bash --out " + script).code, 0);
  EXPECT_TRUE(contains(complete(script, "dynid ide"), "identify"));
  EXPECT_TRUE(contains(complete(script, "dynid ide"), "identifiability"));
  EXPECT_EQ(complete(script, "dynid identify --met"), "--method\n");
  EXPECT_EQ(complete(script, "dynid model ex"), "export\n");
  EXPECT_TRUE(contains(complete(script, "dynid model export --fo"), "--format"));
  EXPECT_TRUE(contains(complete(script, "dynid identify --robot pan"), "panda"));
  EXPECT_TRUE(contains(complete(script, "dynid search --budget"), "--budget-seconds"));
  // Every option of identify's --help is offered.
  const std::string all = complete(script, "dynid identify --");
  for (const char* option : {"--method", "--prior-weight", "--combined-seconds", "--write-urdf"})
    EXPECT_TRUE(contains(all, option)) << option;
}

TEST(CommandTable, ZshCompletionIsValidZsh) {
  const std::string script = test::tempPath("_dynid");
  ASSERT_EQ(run("completion zsh --out " + script).code, 0);
  EXPECT_TRUE(contains(readFile(script), "'--combined-seconds["));
  if (std::system("command -v zsh >/dev/null 2>&1") != 0) GTEST_SKIP() << "no zsh";
  EXPECT_EQ(std::system(("zsh -n " + script).c_str()), 0);
}

TEST(CommandTable, ManPagesForEveryCommandRenderWithoutWarnings) {
  const std::string dir = test::tempPath("man1");
  std::filesystem::remove_all(dir);
  const Result r = run("man --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (std::string command : kCommands) {
    for (char& c : command)
      if (c == ' ') c = '-';
    const std::string page = dir + "/dynid-" + command + ".1";
    ASSERT_TRUE(std::filesystem::exists(page)) << page;
    if (std::system("command -v groff >/dev/null 2>&1") != 0) continue;
    const std::string warnings = test::tempPath("groff_warnings");
    ASSERT_EQ(std::system(("groff -man -Tutf8 -ww -z " + page + " 2>" + warnings).c_str()), 0);
    EXPECT_EQ(readFile(warnings), "") << page;
  }
  EXPECT_TRUE(contains(readFile(dir + "/dynid-identify.1"), "\\-\\-combined\\-seconds"));
  EXPECT_TRUE(contains(readFile(dir + "/dynid.1"), "dynid\\-identify(1)"));
}

}  // namespace
}  // namespace dynid
