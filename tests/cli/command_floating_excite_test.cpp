// excite --floating-base (cli/command_floating_excite.cpp): a standing robot's designed sway, and
// simulate --trajectory along it, on the example quadruped (examples/floating/anymal_c).
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"

namespace dynid {
namespace {

const std::string kStandingQuadruped =
    std::string(DYNID_SOURCE_DIR) + "/examples/floating/anymal_c/anymal.urdf";
const char* kKneesBent = "0,0.5,-1,0,0.5,-1,0,-0.5,1,0,-0.5,1";

/// The design, its document and its console lines; then the robot simulated along it with noise
/// and identified: the sets determine what the design said they would.
TEST(Cli, ExciteAStandingRobotsSwayThenSimulateAndIdentifyAlongIt) {
  const std::string dir = test::tempPath("floating-excite");
  std::filesystem::remove_all(dir);
  test::Result r =
      test::run("excite --robot " + kStandingQuadruped +
                " --floating-base --contacts LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT --stance " +
                kKneesBent + " --friction-cone 0.6 --starts 1 --evaluations 30 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // Every set at what any sway of this stance determines, the default sway below it (measured
  // 93, 94, 90 against 90, 91, 87 of 94).
  EXPECT_TRUE(test::contains(r.out, "torques_contacts: 90 of 94, condition")) << r.out;
  EXPECT_TRUE(test::contains(r.out, "(any sway of this stance: 90); the default sway 87 of 94"))
      << r.out;
  EXPECT_TRUE(test::contains(r.out, "torques_wrenches: 94 of 94, condition")) << r.out;
  EXPECT_TRUE(test::contains(r.out, "of cones of mu 0.6")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/standing_excitation.json"));
  EXPECT_EQ(j["kind"], "dynid.standing_excitation");
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["set"], "torques_contacts");
  EXPECT_EQ(j["design"]["a"].size(), 6u);
  EXPECT_EQ(j["sets"][2]["standing"], 90);
  EXPECT_EQ(j["sets"][2]["default_sway"]["determined"], 87);
  EXPECT_TRUE(j["sets"][2]["default_sway"]["condition"].is_null());  // below the class's rank
  EXPECT_LE(j["designed"]["cone_use"].get<double>(), 1.0);
  EXPECT_EQ(j["provenance"]["seed"], 1);
  EXPECT_TRUE(std::filesystem::exists(dir + "/standing_excitation.md"));

  // simulate takes the stance and the feet from the design: no warning, every split within the
  // cones.
  r = test::run("simulate --robot " + kStandingQuadruped + " --floating-base --trajectory " + dir +
                "/standing_excitation.json --friction-cone 0.6 --noise-tau 0.05 --noise-force "
                "0.2 --noise-moment 0.05 --rate 100 --out " +
                dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(test::contains(r.out, "400 states of the motion of the standing sway of")) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
  r = test::run("identify --robot " + kStandingQuadruped +
                " --floating-base --method ols --segments 5 --data " + dir + "/d.csv --out " + dir +
                "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(test::contains(r.out, "torques_wrenches: 94 base parameters")) << r.out;
  EXPECT_TRUE(test::contains(r.out,
                             "torques_contacts: not estimated: the samples determine 90 of "
                             "the 94"))
      << r.out;
}

/// Names from anyone: the robot and the output folder with a quote, a space and a dollar sign.
/// The command line the console prints to simulate along the design runs as printed.
TEST(Cli, ExcitesPrintedSimulateCommandRunsWithHostileNames) {
  const std::string dir = test::tempPath("it's a $HOME sway");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string robot = dir + "/robot \"quoted\".urdf";
  std::filesystem::copy_file(kStandingQuadruped, robot);
  const auto quoted = [](const std::string& word) {
    std::string out = "'";
    for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  };
  test::Result r =
      test::run("excite --robot " + quoted(robot) +
                " --floating-base --contacts LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT --stance " +
                kKneesBent + " --starts 1 --evaluations 30 --out " + quoted(dir + "/d"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string lead = "simulate along it: dynid ", tail = " --out DATA.csv";
  const std::size_t at = r.out.find(lead), end = r.out.find(tail);
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_NE(end, std::string::npos) << r.out;
  const std::string command = r.out.substr(at + lead.size(), end - at - lead.size());
  r = test::run(command + " --samples 20 --out " + quoted(dir + "/data.csv"));
  ASSERT_EQ(r.code, 0) << command << "\n" << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/data.csv"));
}

}  // namespace
}  // namespace dynid
