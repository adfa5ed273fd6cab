// `dynid` itself: --version, --help, the usage and unknown commands (cli/main.cpp).
#include <sys/wait.h>

#include <algorithm>
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

}  // namespace
}  // namespace dynid
