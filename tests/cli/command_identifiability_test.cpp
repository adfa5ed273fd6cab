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

/// ANYmal C (examples/floating/anymal_c) on its four point feet: every sensor set's count, the
/// drives' columns seen only by joint torques.
TEST(Cli, IdentifiabilityOfAFloatingBase) {
  const std::string dir = test::tempPath("ident-floating");
  const std::string robot =
      std::string(DYNID_SOURCE_DIR) + "/examples/floating/anymal_c/anymal.urdf";
  const Result r = run("identifiability --robot " + robot +
                       " --floating-base --contacts LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT "
                       "--drive-terms fv,fc --out " +
                       dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/floating_identifiability.json"));
  EXPECT_EQ(j["kind"], "dynid.floating_identifiability");
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["motion"], "holding");
  EXPECT_EQ(j["joints"], 12);
  EXPECT_EQ(j["num_standard"], 10 + 12 * 12);  // the base body's 10, each limb's 10 + Fv, Fc
  ASSERT_EQ(j["sets"].size(), 3u);
  const int wrenches = j["sets"][0]["num_base"], full = j["sets"][1]["num_base"];
  const int flags = j["sets"][2]["num_base"];
  // The six base rows see every inertial base parameter the whole body does (Ayusawa et al.
  // 2014), but no friction: the joints' 24 friction parameters are what the torques add.
  EXPECT_EQ(full - wrenches, 24);
  EXPECT_EQ(flags, full);
  EXPECT_EQ(j["gains"][0]["gained"], 24);
  EXPECT_TRUE(contains(r.out, "the joint torques add 24 base parameters to wrenches")) << r.out;
  const std::string md = readFile(dir + "/floating_identifiability.md");
  EXPECT_TRUE(contains(md, "| torques_contacts |")) << md;
}

TEST(Cli, IdentifiabilityOfAFloatingBaseRefusesWhatItCannotUse) {
  const std::string robot =
      std::string(DYNID_SOURCE_DIR) + "/examples/floating/anymal_c/anymal.urdf";
  const std::string dir = test::tempPath("ident-floating-bad");
  // A contact the robot lacks: the field, the name and the links there are.
  Result r =
      run("identifiability --robot " + robot + " --floating-base --contacts LF_PAW --out " + dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "--contacts")) << r.err;
  EXPECT_TRUE(contains(r.err, "'LF_PAW'")) << r.err;
  EXPECT_TRUE(contains(r.err, "LF_FOOT")) << r.err;
  // Floating-only options without --floating-base, an unknown sensor set, a built-in arm.
  EXPECT_EQ(run("identifiability --robot puma560 --contacts a --out " + dir).code, 2);
  r = run("identifiability --robot " + robot + " --floating-base --sensors imu --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--sensors")) << r.err;
  EXPECT_EQ(run("identifiability --robot puma560 --floating-base --out " + dir).code, 1);
  // Holding without contacts.
  r = run("identifiability --robot " + robot + " --floating-base --motion holding --out " + dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "--contacts")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/floating_identifiability.json"));
}

}  // namespace
}  // namespace dynid
