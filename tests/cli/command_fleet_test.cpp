// dynid fleet through the executable: robots' logs in folders of their own, the robot carrying an
// undeclared mass found, and the same fleet from the robots' summaries.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

using test::run;

TEST(Cli, FleetFindsTheRobotWithAnUndeclaredMassFromLogsOrSummaries) {
  const std::string dir = test::tempPath("cli_fleet");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // The heavy arm: the PUMA with 3 kg more at link 3's origin.
  ASSERT_EQ(
      run("model export --robot puma560 --drives --format json --out " + dir + "/heavy.json").code,
      0);
  auto model = nlohmann::json::parse(readFile(dir + "/heavy.json"));
  model["bodies"][2]["inertial"]["m"] = model["bodies"][2]["inertial"]["m"].get<double>() + 3.0;
  std::ofstream(dir + "/heavy.json") << model.dump();
  std::string logs, summaries;
  const std::vector<std::string> robots = {"arm1", "arm2", "arm3", "arm4", "heavy"};
  for (std::size_t r = 0; r < robots.size(); ++r) {
    const std::string& robot = robots[r];
    std::filesystem::create_directories(dir + "/" + robot);
    for (int part = 1; part <= 2; ++part) {
      const std::string log = dir + "/" + robot + "/log" + std::to_string(part) + ".csv";
      const std::string spec = robot == "heavy" ? dir + "/heavy.json" : "puma560 --drives";
      ASSERT_EQ(run("simulate --robot " + spec +
                    " --controller fourier --duration 3 --noise-tau 0.1 --seed " +
                    std::to_string(10 * r + part) + " --out " + log)
                    .code,
                0);
      logs += " " + log;
    }
    ASSERT_EQ(run("summarize --robot puma560 --drives --data " + dir + "/" + robot + "/log1.csv " +
                  dir + "/" + robot + "/log2.csv --merge --out " + dir + "/s/" + robot)
                  .code,
              0);
    summaries += " " + dir + "/s/" + robot + "/summary.json";
  }
  const test::Result from_logs =
      run("fleet --robot puma560 --drives --data" + logs + " --out " + dir + "/fleet");
  ASSERT_EQ(from_logs.code, 0) << from_logs.err;
  EXPECT_NE(from_logs.out.find("1 of 5 robots lies outside the fleet: heavy"), std::string::npos)
      << from_logs.out;
  const auto fleet = nlohmann::json::parse(readFile(dir + "/fleet/fleet.json"));
  ASSERT_EQ(fleet["robots"].size(), 5u);
  EXPECT_EQ(fleet["provenance"]["inputs"].size(), 10u);  // the ten logs, hashed
  for (const auto& robot : fleet["robots"]) {
    EXPECT_EQ(robot["outside"].get<bool>(), robot["name"] == "heavy") << robot["name"];
    EXPECT_EQ(robot["logs"].size(), 2u);
  }
  const test::Result from_summaries =
      run("fleet --robot puma560 --drives --summaries" + summaries + " --out " + dir + "/fleet_s");
  ASSERT_EQ(from_summaries.code, 0) << from_summaries.err;
  const auto again = nlohmann::json::parse(readFile(dir + "/fleet_s/fleet.json"));
  // The same summaries, merged in the same order: the same bits.
  for (std::size_t r = 0; r < 5; ++r) {
    EXPECT_EQ(again["robots"][r]["estimate"], fleet["robots"][r]["estimate"]);
    EXPECT_EQ(again["robots"][r]["posterior"], fleet["robots"][r]["posterior"]);
  }
  EXPECT_EQ(again["verdict"], fleet["verdict"]);
  // A manifest naming the same robots and logs (paths beside it): the same fleet.
  nlohmann::json manifest = {{"schema_version", 1}, {"kind", "dynid.fleet_manifest"}};
  for (const std::string& robot : robots)
    manifest["robots"].push_back(
        {{"name", robot}, {"data", {robot + "/log1.csv", robot + "/log2.csv"}}});
  std::ofstream(dir + "/fleet_manifest.json") << manifest.dump();
  const test::Result from_manifest = run("fleet --robot puma560 --drives --manifest " + dir +
                                         "/fleet_manifest.json --out " + dir + "/fleet_m");
  ASSERT_EQ(from_manifest.code, 0) << from_manifest.err;
  const auto listed = nlohmann::json::parse(readFile(dir + "/fleet_m/fleet.json"));
  for (std::size_t r = 0; r < 5; ++r)
    EXPECT_EQ(listed["robots"][r]["estimate"], fleet["robots"][r]["estimate"]);
}

}  // namespace
}  // namespace dynid
