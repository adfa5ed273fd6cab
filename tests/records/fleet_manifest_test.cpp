#include "analysis/records/fleet_manifest.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(FleetManifest, ReadsTheRobotsWithPathsBesideTheManifest) {
  const std::vector<FleetManifestRobot> robots = fleetManifestFrom(
      R"({"schema_version": 1, "kind": "dynid.fleet_manifest", "description": "cell 3",
          "robots": [{"name": "a", "data": ["a1.csv", "/abs/a2.csv"]},
                     {"name": "b", "summaries": ["sums/b.summary.json"]}]})",
      "cell/fleet.json");
  ASSERT_EQ(robots.size(), 2u);
  EXPECT_EQ(robots[0].name, "a");
  EXPECT_EQ(robots[0].data, (std::vector<std::string>{"cell/a1.csv", "/abs/a2.csv"}));
  EXPECT_TRUE(robots[0].summaries.empty());
  EXPECT_EQ(robots[1].summaries, std::vector<std::string>{"cell/sums/b.summary.json"});
}

TEST(FleetManifest, RefusesWhatCannotBeMeantNamingTheField) {
  const auto refused = [](const std::string& robots, const std::string& field) {
    const std::string text =
        R"({"schema_version": 1, "kind": "dynid.fleet_manifest", "robots": )" + robots + "}";
    try {
      fleetManifestFrom(text, "m.json");
      ADD_FAILURE() << robots;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  refused(R"([{"name": "a", "data": ["x.csv"], "summaries": ["y.json"]}])", "robots[0]");
  refused(R"([{"name": "a"}])", "robots[0]");
  refused(R"([{"data": ["x.csv"]}])", "robots[0].name");
  refused(R"([{"name": "", "data": ["x.csv"]}])", "robots[0].name");
  refused(R"([{"name": "a", "data": []}])", "robots[0].data");
  refused(R"([{"name": "a", "data": [3]}])", "robots[0].data[0]");
  refused(R"([{"name": "a", "data": ["x"]}, {"name": "a", "data": ["y"]}])", "robots[1].name");
  refused(R"([{"name": "a", "logs": ["x"]}])", "robots[0].logs");
  refused(R"({"a": ["x"]})", "robots");
  EXPECT_THROW(fleetManifestFrom(R"({"schema_version": 1, "kind": "dynid.summary", "robots": []})",
                                 "m.json"),
               ParseError);
}

}  // namespace
}  // namespace dynid
