// `dynid` itself: --version, --help, the usage and unknown commands (cli/main.cpp).
#include <sys/wait.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, VersionHelpAndUsage) {
  EXPECT_EQ(run("--version").code, 0);
  EXPECT_TRUE(contains(run("--help").out, "commands:"));
  EXPECT_EQ(run("").code, 2);
  const Result unknown = run("fly");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_TRUE(contains(unknown.err, "unknown command 'fly'"));
  for (const char* command : {"dynamics", "simulate", "model show", "model check", "model export",
                              "identifiability", "identify", "search", "refine"}) {
    const Result help = run(std::string(command) + " --help");
    EXPECT_EQ(help.code, 0) << command;
    EXPECT_TRUE(contains(help.out, "usage: dynid")) << command;
  }
}

TEST(Cli, CtrlCDuringALongReadLeavesNothing) {
  // The data come through a FIFO that stops after 1500 of 3001 rows and stays open, so each
  // command is still reading when SIGINT arrives (exit 130 proves it was running: a refusal would
  // have exited 1 before). It must end by that signal and leave nothing in its --out: no output,
  // no temporary.
  const std::string dir = test::tempPath("interrupt_read");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + dir + "/train.csv").code, 0);
  ASSERT_EQ(run("identify --robot puma560 --data " + dir + "/train.csv --out " + dir + "/est").code,
            0);
  for (const std::string command : {"identify --robot puma560 --data pipe --out out",
                                    "identify --robot puma560 --method pc --data pipe --out out",
                                    "identifiability --robot puma560 --data pipe --out out",
                                    "predict --estimate est/estimate.json --data pipe --out out"}) {
    std::filesystem::remove_all(dir + "/out");
    std::filesystem::remove(dir + "/pipe");
    const std::string script = "cd " + dir + " && mkfifo pipe && " +
                               "{ (head -n 1500 train.csv; exec sleep 30) > pipe & writer=$!; " +
                               DYNID_BIN + " " + command +
                               " >/dev/null 2>&1 & pid=$!; sleep 1; kill -INT $pid; wait $pid; " +
                               "code=$?; kill $writer; exit $code; }";
    const int status = std::system(("bash -c '" + script + "'").c_str());
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << command;
    std::error_code error;
    EXPECT_TRUE(!std::filesystem::exists(dir + "/out") ||
                std::filesystem::is_empty(dir + "/out", error))
        << command;
  }
}

}  // namespace
}  // namespace dynid
