#include "reports/fleet_report.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "analysis/runs/summarize.hpp"
#include "data/io.hpp"
#include "data/puma560.hpp"
#include "tests/common/identification.hpp"

namespace dynid {
namespace {

/// Four PUMA robots from 2 s logs, the last with 3 kg more on link 3 (outside the fleet).
const FleetOutcome& pumaFleet() {
  static const FleetOutcome outcome = [] {
    static std::vector<Summary> summaries;
    for (int r = 0; r < 4; ++r) {
      Model truth = makePuma560(true);
      Eigen::VectorXd theta = truth.standardParameters();
      const int per = truth.parameterLayout().perLink();
      theta.head(3 * per) *= 1.0 + 0.01 * r;
      if (r == 3) theta[2 * per] += 3.0;
      truth.setStandardParameters(theta);
      static std::vector<Trajectory> logs(4);
      logs[static_cast<std::size_t>(r)] = test::pumaTrajectory(truth, 2.0, 0.1, 1 + r);
      SummarizeRequest s;
      s.model = makePuma560(true);
      s.robot_spec = "puma560";
      s.data = &logs[static_cast<std::size_t>(r)];
      summaries.push_back(summarizeRun(s).summaries.front());
    }
    FleetRequest request;
    request.model = makePuma560(true);
    request.robot_spec = "puma560";
    for (int r = 0; r < 4; ++r)
      request.robots.push_back(
          {"arm <" + std::to_string(r) + ">", {}, {}, &summaries[static_cast<std::size_t>(r)]});
    return fleetRun(request);
  }();
  return outcome;
}

TEST(FleetReport, JsonHasThePriorTheRobotsAndTheVerdict) {
  const FleetOutcome& o = pumaFleet();
  const nlohmann::json doc = fleetJson(o);
  EXPECT_EQ(doc["kind"], "dynid.fleet");
  EXPECT_EQ(doc["schema_version"], 1);
  EXPECT_EQ(doc["method"], "ols");
  EXPECT_EQ(doc["covariance"], "hac");
  ASSERT_EQ(doc["robots"].size(), 4u);
  ASSERT_EQ(doc["parameters"].size(), o.base_names.size());
  const nlohmann::json& odd = doc["robots"][3];
  EXPECT_EQ(odd["name"], "arm <3>");
  EXPECT_TRUE(odd["outside"].get<bool>());
  EXPECT_FALSE(odd["learnt_from"].get<bool>());
  EXPECT_GE(odd["outside_parameters"].size(), 1u);
  EXPECT_EQ(odd["posterior"], odd["estimate"]);  // outside: its own estimate
  EXPECT_EQ(odd["estimate"].size(), o.base_names.size());
  int listed = 0;
  for (const auto& p : doc["parameters"])
    for (const auto& name : p["robots_outside"]) listed += name == "arm <3>" ? 1 : 0;
  EXPECT_EQ(listed, static_cast<int>(odd["outside_parameters"].size()));
  EXPECT_EQ(doc["verdict"], o.verdict);
  EXPECT_NE(o.verdict.find("arm <3>"), std::string::npos) << o.verdict;
  EXPECT_TRUE(doc.contains("model"));
}

TEST(FleetReport, WritesTheSetWithTheVerdictFirst) {
  const std::string dir = test::tempPath("fleet_report");
  std::filesystem::remove_all(dir);
  const std::string console = writeFleet(dir, pumaFleet());
  EXPECT_NE(console.find("fleet.json"), std::string::npos);
  const std::string md = readFile(dir + "/report.md");
  const std::size_t verdict = md.find("Verdict"), robots = md.find("## Robots");
  ASSERT_NE(verdict, std::string::npos);
  ASSERT_NE(robots, std::string::npos);
  EXPECT_LT(verdict, robots);
  const std::string html = readFile(dir + "/report.html");
  EXPECT_EQ(html.find("arm <3>"), std::string::npos);  // escaped
  EXPECT_NE(html.find("arm &lt;3&gt;"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(readFile(dir + "/fleet.json")), fleetJson(pumaFleet()));
}

}  // namespace
}  // namespace dynid
