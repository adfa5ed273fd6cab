// dynid excite: the designed motion, its files, and its refusals.
#include <cmath>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, ExciteWritesTheDesignItsTrajectoryAndAReport) {
  const std::string dir = test::tempPath("excite");
  const Result r =
      run("excite --robot puma560 --segments 10 --starts 2 --evaluations 300 --threads 2 "
          "--csv-rate 100 --seed 3 --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "every limit holds at 1000 Hz")) << r.out;
  EXPECT_TRUE(contains(r.out, "note: the model gives no velocity limit")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/excitation.json"));
  EXPECT_EQ(j["schema_version"], 5);
  EXPECT_EQ(j["kind"], "dynid.excitation");
  EXPECT_TRUE(j["stand"].is_null());  // no --stands
  // The robot designed for, embedded: a dynid model the design can be rerun on anywhere.
  EXPECT_EQ(j["model"]["name"], "puma560");
  EXPECT_EQ(j["model_source"],
            (nlohmann::json{{"spec", "puma560"}, {"file", nullptr}, {"sha256", nullptr}}));
  EXPECT_EQ(j["criterion"], "cond");
  EXPECT_TRUE(j["payload_link"].is_null());
  EXPECT_EQ(j["design"]["a"].size(), 6u);
  EXPECT_EQ(j["design"]["a"][0].size(), 5u);
  EXPECT_EQ(j["base_parameters"].size(), 36u);
  EXPECT_TRUE(j["check"]["violations"].empty());
  EXPECT_LT(j["designed"]["condition_unit"].get<double>(),
            j["default_sinusoid"]["condition_unit"].get<double>());
  EXPECT_EQ(j["optimiser"]["seed"], 3);
  // The trajectory: a header, then 10 s at 100 Hz inclusive, at rest at both ends.
  std::istringstream csv(readFile(dir + "/excitation.csv"));
  std::string line, first, last;
  std::getline(csv, line);
  EXPECT_EQ(line.substr(0, 12), "t,q1,q2,q3,q");
  int rows = 0;
  while (std::getline(csv, line)) {
    if (rows == 0) first = line;
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, 1001);
  EXPECT_EQ(last.substr(0, 3), "10,");
  for (const std::string& row : {first, last}) {
    std::vector<double> values;
    std::istringstream fields(row);
    for (std::string f; std::getline(fields, f, ',');) values.push_back(std::stod(f));
    ASSERT_EQ(values.size(), 19u);
    for (int k = 7; k < 19; ++k) EXPECT_LT(std::abs(values[k]), 1e-12) << row;  // dq, ddq
  }
  for (const char* file : {"report.md", "report.html"})
    EXPECT_TRUE(contains(readFile(dir + "/" + file), "default sinusoid")) << file;
  EXPECT_TRUE(test::opensWithVerdict(readFile(dir + "/report.html"),
                                     {"Designed", "How well", "Not determined", "Limits", "Next"}));
}

TEST(Cli, ExcitePayloadDesignsForTheLastLinksTenParameters) {
  const std::string dir = test::tempPath("excite_payload");
  const Result r =
      run("excite --robot puma560 --payload --segments 10 --starts 1 --evaluations "
          "200 --check-rate 200 --horizon 0.05 --csv-rate 50 --payload-proximal-share 0.3 --out " +
          dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/excitation.json"));
  EXPECT_EQ(j["payload_link"], "link6");
  EXPECT_EQ(j["criterion"], "d-optimal");  // the payload's default
  EXPECT_EQ(j["design"]["period"], 15.0);  // the payload's default
  // The criteria are of link 6's 10 parameters, all of them seen with the arm known.
  ASSERT_EQ(j["base_parameters"].size(), 10u);
  EXPECT_EQ(j["base_parameters"][0], "m6");
  EXPECT_TRUE(contains(readFile(dir + "/report.md"), "A payload motion")) << r.out;
  // Mainly the wrist (--payload-proximal-share 0.3): joints 1 to 3 within the middle 30 % of
  // their range.
  EXPECT_TRUE(contains(j["limits"]["notes"].dump(), "joints 1 to 3 kept within 30 %"))
      << j["limits"]["notes"].dump();
  EXPECT_NEAR(j["limits"]["q_max"][0].get<double>() - j["limits"]["q_min"][0].get<double>(),
              0.3 * 2 * 2.792526803190927, 1e-12);
  EXPECT_NEAR(j["limits"]["q_max"][5].get<double>(), 4.642575810304916, 1e-12);  // the wrist's own
  const Result refused = run("excite --robot puma560 --payload-link base --out " + dir + "x");
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(contains(refused.err, "--payload-link")) << refused.err;
  const Result unused =
      run("excite --robot puma560 --payload-proximal-share 0.5 --out " + dir + "x");
  EXPECT_EQ(unused.code, 2);
  EXPECT_TRUE(contains(unused.err, "--payload")) << unused.err;
}

TEST(Cli, ExciteIsTheSameForAnyThreadCount) {
  const std::string a = test::tempPath("excite_t1"), b = test::tempPath("excite_t2");
  const std::string common =
      "excite --robot puma560 --segments 10 --starts 3 --evaluations 100 --seed 5 ";
  ASSERT_EQ(run(common + "--threads 1 --out " + a).code, 0);
  ASSERT_EQ(run(common + "--threads 2 --out " + b).code, 0);
  const auto ja = nlohmann::json::parse(readFile(a + "/excitation.json"));
  const auto jb = nlohmann::json::parse(readFile(b + "/excitation.json"));
  EXPECT_EQ(ja["design"], jb["design"]);
  EXPECT_EQ(ja["designed"], jb["designed"]);
  EXPECT_EQ(readFile(a + "/excitation.csv"), readFile(b + "/excitation.csv"));
}

TEST(Cli, ExciteRefusesImpossibleSettings) {
  const std::string dir = test::tempPath("excite_bad");
  struct Case {
    std::string args;
    int code;
    std::string names;
  };
  for (const Case& c : std::vector<Case>{
           {"--harmonics 1", 2, "--harmonics"},
           {"--period 0", 2, "--period"},
           {"--criterion gc-typo", 2, "unknown criterion"},
           {"--dq-max 0", 2, "velocity limit"},
           {"--q-min 1 --q-max 0.5", 2, "position range"},
           {"--offset 9", 2, "--offset"},
           {"--floor 5", 1, "floor"},
       }) {
    const Result r = run("excite --robot puma560 --segments 10 --starts 1 --evaluations 20 " +
                         c.args + " --out " + dir);
    EXPECT_EQ(r.code, c.code) << c.args << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.names)) << c.args << ": " << r.err;
  }
}

}  // namespace
}  // namespace dynid
