// dynid identifiability: the base parameters report.
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

TEST(Cli, IdentifiabilityReport) {
  const std::string dir = test::tempPath("ident");
  const Result r = run("identifiability --robot puma560 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "60 standard parameters, 36 base parameters")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/identifiability.json"));
  EXPECT_EQ(j["schema_version"], 2);
  EXPECT_EQ(j["provenance"]["command"][1], "identifiability");
  EXPECT_EQ(j["robot"], "puma560");
  EXPECT_EQ(j["num_standard"], 60);
  EXPECT_EQ(j["num_base"], 36);
  EXPECT_GT(j["rank_gap"].get<double>(), 1e8);
  ASSERT_EQ(j["base_parameters"].size(), 36u);
  for (const char* key : {"name", "expression", "coefficients"})
    EXPECT_TRUE(j["base_parameters"][0].contains(key)) << key;
  EXPECT_EQ(j["unidentifiable"].size(), 9u);
  EXPECT_EQ(j["null_space"]["basis"].size(), 24u);
  EXPECT_TRUE(j["condition_number"].is_number());
  const std::string md = readFile(dir + "/identifiability.md");
  EXPECT_TRUE(contains(md, "| 36 | Izz6 | `Izz6` |")) << md;
}

}  // namespace
}  // namespace dynid
