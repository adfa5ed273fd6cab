// The floating-base branches (cli/command_floating.cpp): identifiability, simulate, prepare and
// identify with --floating-base, on the example quadruped and humanoid (examples/floating/).
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/floating_bag.hpp"
#include "tests/common/floating_models.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

const std::string kAnymal =
    std::string(DYNID_SOURCE_DIR) + "/examples/floating/anymal_c/anymal.urdf";
const std::string kRomeo =
    std::string(DYNID_SOURCE_DIR) + "/examples/floating/romeo/romeo_small.urdf";
const char* kFeet = "LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT";

/// ANYmal C (examples/floating/anymal_c) on its four point feet: every sensor set's count, the
/// drives' columns seen only by joint torques.
TEST(Cli, IdentifiabilityOfAFloatingBase) {
  const std::string dir = test::tempPath("ident-floating");
  const std::string& robot = kAnymal;
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
  const std::string& robot = kAnymal;
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

/// simulate writes a floating dataset; identify estimates every set it feeds, and the noise-free
/// estimate is the model's own base parameters (the humanoid on its soles: frame contacts).
TEST(Cli, SimulateAndIdentifyAFloatingBase) {
  const std::string dir = test::tempPath("floating-identify");
  std::filesystem::create_directories(dir);
  for (const char* seed : {"1", "2"}) {
    const Result r = run("simulate --robot " + kRomeo +
                         " --floating-base --contacts l_sole:frame,r_sole:frame --samples 60 "
                         "--seed " +
                         std::string(seed) + " --out " + dir + "/d" + seed + ".csv");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "60 random states")) << r.out;
  }
  const Result r = run("identify --robot " + kRomeo + " --floating-base --method ols --data " +
                       dir + "/d1.csv --validate " + dir + "/d2.csv --out " + dir + "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "torques_contacts:")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/est/floating_identification.json"));
  EXPECT_EQ(j["kind"], "dynid.floating_identification");
  EXPECT_EQ(j["schema_version"], 4);
  EXPECT_EQ(j["method"], "ols");
  EXPECT_EQ(j["motion"], "holding");
  // Random states: no GC error, and why (the motion test of analysis/floating/gc_data.hpp).
  EXPECT_TRUE(contains(j["gc"]["refused"].get<std::string>(), "not one motion")) << j["gc"];
  EXPECT_TRUE(j["sets"][0]["gc_error"]["train"].is_null());
  EXPECT_EQ(j["contacts"][0]["kind"], "frame");
  EXPECT_EQ(j["validation"]["samples"], 60);
  ASSERT_EQ(j["sets"].size(), 3u);
  for (const auto& set : j["sets"]) {
    ASSERT_TRUE(set["refused"].is_null()) << set["refused"];
    // Noise-free: 1e-9 relative (the issue's), in percent.
    EXPECT_LT(set["model_error_percent"].get<double>(), 1e-7) << set["sensors"];
    EXPECT_LT(set["validation_percent"].get<double>(), 1e-7) << set["sensors"];
    EXPECT_EQ(set["base_parameters"].size(), set["num_base"]);
  }
  EXPECT_TRUE(j.contains("provenance"));
  const std::string md = readFile(dir + "/est/floating_identification.md");
  EXPECT_TRUE(contains(md, "| torques_wrenches |")) << md;
}

/// With noise and wls (the default), each channel's noise comes out of the data.
TEST(Cli, IdentifyAFloatingBaseEstimatesItsNoise) {
  const std::string dir = test::tempPath("floating-noise");
  std::filesystem::create_directories(dir);
  Result r = run("simulate --robot " + kAnymal + " --floating-base --contacts " + kFeet +
                 " --samples 300 --noise-tau 0.5 --noise-force 2 --out " + dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("identify --robot " + kAnymal + " --floating-base --data " + dir + "/d.csv --out " + dir +
          "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/est/floating_identification.json"));
  EXPECT_EQ(j["method"], "wls");
  const auto& noise = j["sets"][1]["noise_sd"];
  EXPECT_EQ(noise["estimated_by"], "torques_wrenches");
  // Thousands of residuals: each sd within a few percent of the simulated; 10 % is the bound.
  EXPECT_NEAR(noise["torque"].get<double>(), 0.5, 0.05);
  EXPECT_NEAR(noise["force"].get<double>(), 2.0, 0.2);
  EXPECT_TRUE(noise["moment"].is_null());  // point feet carry no moment
  EXPECT_TRUE(j["sets"][1]["physical"].is_null());
  // pc: weighted the same, every body consistent; its prior weight is refused with another method.
  r = run("identify --robot " + kAnymal + " --floating-base --method pc --data " + dir +
          "/d.csv --sensors torques_wrenches --out " + dir + "/pc");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "physically consistent in")) << r.out;
  const auto pc = nlohmann::json::parse(readFile(dir + "/pc/floating_identification.json"));
  EXPECT_EQ(pc["method"], "pc");
  EXPECT_TRUE(pc["sets"][0]["physical"]["converged"].get<bool>());
  EXPECT_EQ(pc["sets"][0]["physical"]["standard"].size(), pc["standard_parameters"].size());
  EXPECT_NEAR(pc["sets"][0]["noise_sd"]["torque"].get<double>(), 0.5, 0.05);
  r = run("identify --robot " + kAnymal + " --floating-base --prior-weight 2 --data " + dir +
          "/d.csv --out " + dir + "/x");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--prior-weight applies to --method pc")) << r.err;
}

/// A 2 kg box bolted to ANYmal's base (a fixed link in a copy of its URDF): simulated on the loaded
/// robot, estimated with the unloaded one's URDF and --payload-link.
TEST(Cli, IdentifyAPayloadOnAFloatingBase) {
  const std::string dir = test::tempPath("floating-payload");
  std::filesystem::create_directories(dir);
  std::string urdf = readFile(kAnymal);
  const std::string box = R"(<link name="box"><inertial><mass value="2.0"/>)"
                          R"(<inertia ixx="0.006" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.01"/>)"
                          R"(</inertial></link><joint name="box_mount" type="fixed">)"
                          R"(<parent link="base"/><child link="box"/><origin xyz="0.1 0 0.15"/>)"
                          R"(</joint></robot>)";
  urdf.replace(urdf.rfind("</robot>"), 8, box);
  const std::string loaded = dir + "/loaded.urdf";
  std::ofstream(loaded) << urdf;
  Result r = run("simulate --robot " + loaded + " --floating-base --contacts " + kFeet +
                 " --samples 100 --out " + dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --data " + dir +
          "/d.csv --payload-link base --out " + dir + "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "payload on base from wrenches: 2 ")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/est/floating_identification.json"));
  ASSERT_EQ(j["payload"]["sets"].size(), 3u);
  for (const auto& set : j["payload"]["sets"]) {
    // Noise-free: 1e-9 relative.
    EXPECT_NEAR(set["mass"].get<double>(), 2.0, 2e-9) << set["sensors"];
    EXPECT_NEAR(set["com"][0].get<double>(), 0.1, 1e-9) << set["sensors"];
    EXPECT_NEAR(set["com"][2].get<double>(), 0.15, 1e-9) << set["sensors"];
  }
  // From a loaded/unloaded pair, the robot's parameters unused (noise-free: exact).
  r = run("simulate --robot " + kAnymal + " --floating-base --contacts " + kFeet +
          " --samples 100 --seed 2 --out " + dir + "/u.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --data " + dir +
          "/d.csv --unloaded " + dir + "/u.csv --payload-link base --out " + dir + "/pair");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "(from the unloaded data; residual scale")) << r.out;
  const auto pair = nlohmann::json::parse(readFile(dir + "/pair/floating_identification.json"));
  EXPECT_EQ(pair["payload"]["from"], "unloaded_data");
  for (const auto& set : pair["payload"]["sets"])
    EXPECT_NEAR(set["mass"].get<double>(), 2.0, 1e-8) << set["sensors"];  // two fits' round-off
  r = run("identify --robot " + kAnymal + " --floating-base --data " + dir + "/d.csv --unloaded " +
          dir + "/u.csv --out " + dir + "/x");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--unloaded needs --payload-link")) << r.err;
  // Only with --floating-base; a link the robot lacks.
  EXPECT_EQ(run("identify --robot puma560 --data " + dir + "/d.csv --payload-link base --out " +
                dir + "/x")
                .code,
            2);
  r = run("identify --robot " + kAnymal + " --floating-base --data " + dir +
          "/d.csv --payload-link backpack --out " + dir + "/x");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "--payload-link: 'backpack'")) << r.err;
}

/// The dataset to standard output, read back from a file.
TEST(Cli, SimulateAFloatingBaseToStandardOutput) {
  const Result r = run("simulate --robot " + kAnymal +
                       " --floating-base --motion suspended --samples 4 --out -");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrench:base:nx")) << r.out;  // the support, at the base link
  EXPECT_TRUE(contains(r.err, "suspended")) << r.err;
}

/// A suspended robot's recording (joints, IMU and force-torque sensor at three rates) prepared
/// into a floating dataset, then identified from it.
TEST(Cli, PrepareAFloatingRecordingThenIdentifyIt) {
  const FloatingModel model = test::loadExample(test::kAnymalExample);
  const std::string bag = test::tempPath("suspended-cli.db3");
  test::writeSuspendedRecording(bag, model, test::SuspendedMotion(model, 2), {});
  const std::string dir = test::tempPath("prepare-floating");
  Result r = run("prepare --floating-base --robot " + kAnymal + " --log " + bag + " --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/floating_prepare.json"));
  EXPECT_EQ(j["kind"], "dynid.floating_prepare");
  EXPECT_EQ(j["schema_version"], 2);
  EXPECT_TRUE(j["contact_threshold"].is_null());
  ASSERT_EQ(j["topics"].size(), 3u);
  EXPECT_EQ(j["topics"][1]["frame"], "imu_link");
  EXPECT_EQ(j["cutoff"], 10.0);
  EXPECT_EQ(j["runs"], 1);
  EXPECT_TRUE(j["torques"].get<bool>());
  EXPECT_TRUE(contains(r.out, "/ft (geometry_msgs/msg/WrenchStamped, in face_rear)")) << r.out;
  EXPECT_TRUE(contains(r.out, "every topic resampled to")) << r.out;
  r = run("identify --floating-base --robot " + kAnymal + " --data " + dir +
          "/floating_dataset.csv --method ols --sensors wrenches --out " + dir + "/id");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto id = nlohmann::json::parse(readFile(dir + "/id/floating_identification.json"));
  // The sensor's frame is on the base body, and its support turns and moves the robot.
  EXPECT_EQ(id["motion"], "carried");
  EXPECT_TRUE(contains(r.err, "its support moves the base (carried) by the data")) << r.err;
  // Contact flags from the sensor's force (the robot weighs about 500 N): the dataset then feeds
  // the torques with contact flags.
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + bag +
          " --contact-threshold 300 --out " + dir + "/flags");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "contact flags where the force reaches 300 N: face_rear holds in"))
      << r.out;
  const auto flags = nlohmann::json::parse(readFile(dir + "/flags/floating_prepare.json"));
  EXPECT_EQ(flags["contact_threshold"], 300.0);
  ASSERT_EQ(flags["thresholded_contacts"].size(), 1u);
  r = run("identify --floating-base --robot " + kAnymal + " --data " + dir +
          "/flags/floating_dataset.csv --method ols --sensors torques_contacts --out " + dir +
          "/flags/id");
  ASSERT_EQ(r.code, 0) << r.err;
  // What cannot be used is said with this command's flags: a topic the recording lacks (exit 1),
  // options that need --floating-base or do not apply to it (exit 2).
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + bag +
          " --imu-topic /imu/data --out " + dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "no topic '/imu/data' (--imu-topic)")) << r.err;
  r = run("prepare --robot " + kAnymal + " --log " + bag + " --imu-topic /imu --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--imu-topic needs --floating-base")) << r.err;
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + bag + " --cutoff auto --out " +
          dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--cutoff auto (from q's spectrum) does not apply")) << r.err;
  // The same sensors as one table's columns, each row one sensor's sample.
  const std::string table = test::tempPath("suspended-cli.csv");
  test::writeSuspendedTable(table, model, test::SuspendedMotion(model, 2), {});
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + table + " --out " + dir +
          "/table");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto t = nlohmann::json::parse(readFile(dir + "/table/floating_prepare.json"));
  EXPECT_EQ(t["topics"][0]["topic"], "q:*");
  EXPECT_EQ(t["topics"][3]["topic"], "contact:face_rear");
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + table +
          " --imu-topic /imu --out " + dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err,
                       "--topic, --imu-topic, --wrench-topics, --contact-topics and --stamp "
                       "apply to recordings, not to a table"))
      << r.err;
  r = run("prepare --floating-base --robot " + kAnymal + " --log " + bag + " --decimate 2 --out " +
          dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--decimate does not apply to prepare --floating-base")) << r.err;
}

/// A design `dynid excite` made for ANYmal with its base fixed
/// (tests/data/floating/fixtures/anymal_excitation.json), simulated on the suspended robot.
TEST(Cli, SimulateADesignOnASuspendedFloatingBase) {
  const std::string dir = test::tempPath("floating-design");
  std::filesystem::create_directories(dir);
  const Result r = run("simulate --robot " + kAnymal + " --floating-base --trajectory " +
                       std::string(DYNID_SOURCE_DIR) +
                       "/tests/data/floating/fixtures/anymal_excitation.json --samples 100 "
                       "--out " +
                       dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "suspended): 100 states of the design over one period")) << r.out;
  const std::string csv = readFile(dir + "/d.csv");
  EXPECT_TRUE(contains(csv, "wrench:base:nx")) << csv.substr(0, 400);  // the support's sensor
}

/// excite --stands chooses the stand orientations for a suspended robot's design (upright first;
/// excitation.json's `stand`, the report's section, the console's lines), and simulate runs the
/// design at them unless --stand-tilts says otherwise: every set is then estimated.
TEST(Cli, ExciteChoosesStandTiltsThatSimulateUses) {
  const std::string dir = test::tempPath("floating-stands");
  std::filesystem::create_directories(dir);
  Result r = run("excite --robot " + kAnymal +
                 " --starts 1 --evaluations 50 --period 5 --stands 3 --max-tilt 0.3 --tilt-grid "
                 "5 --out " +
                 dir + "/ex");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "stand orientations (roll, pitch) [rad]: (0, 0), ")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrenches: 80 of 80, condition ")) << r.out;
  EXPECT_TRUE(contains(r.out, "(upright alone 79 of 80)")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/ex/excitation.json"));
  ASSERT_EQ(j["stand"]["tilts"].size(), 3u);
  EXPECT_EQ(j["stand"]["tilts"][0], nlohmann::json({0.0, 0.0}));
  EXPECT_EQ(j["stand"]["candidates"], 25);
  for (const auto& tilt : j["stand"]["tilts"])
    for (const auto& angle : tilt) EXPECT_LE(std::abs(angle.get<double>()), 0.3 + 1e-15);
  EXPECT_TRUE(j["stand"]["sets"][0]["upright"]["condition"].is_null());
  EXPECT_TRUE(contains(readFile(dir + "/ex/report.md"), "## Stand orientations"));
  r = run("simulate --robot " + kAnymal + " --floating-base --trajectory " + dir +
          "/ex/excitation.json --samples 100 --out " + dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "300 states of the design, one period at each of 3 stand")) << r.out;
  EXPECT_TRUE(contains(r.out, "the stand orientations the design chose")) << r.out;
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --segments 1 --data " +
          dir + "/d.csv --out " + dir + "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(contains(r.out, "not estimated")) << r.out;
  // --stand-tilts overrides the design's: upright alone leaves the wrench sets refused.
  r = run("simulate --robot " + kAnymal + " --floating-base --trajectory " + dir +
          "/ex/excitation.json --stand-tilts 0,0 --samples 100 --out " + dir + "/upright.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(contains(r.out, "the design chose")) << r.out;
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --segments 1 --data " +
          dir + "/upright.csv --out " + dir + "/upright");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrenches: not estimated: the samples determine 79 of the 80"))
      << r.out;
}

/// identify measures each estimate's GC error on a motion (the design at 500 Hz), beside the
/// model's own; --horizon and --segments set the segments.
TEST(Cli, IdentifyAFloatingBaseMeasuresTheGcErrorOnAMotion) {
  const std::string dir = test::tempPath("floating-gc");
  std::filesystem::create_directories(dir);
  Result r = run("simulate --robot " + kAnymal + " --floating-base --trajectory " +
                 std::string(DYNID_SOURCE_DIR) +
                 "/tests/data/floating/fixtures/anymal_excitation.json --samples 5000 --out " +
                 dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --sensors " +
          "torques_contacts --horizon 0.02 --segments 20 --data " + dir + "/d.csv --out " + dir +
          "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "GC error of the model's own parameters")) << r.out;
  EXPECT_TRUE(contains(r.out, "20 segments of 0.02 s")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/est/floating_identification.json"));
  const auto& gc = j["gc"];
  ASSERT_TRUE(gc["refused"].is_null()) << gc;
  EXPECT_EQ(gc["samples_per_segment"], 10);  // 0.02 s at 500 Hz
  EXPECT_EQ(gc["segments_train"], 20);
  EXPECT_TRUE(gc["model_noise_floor"]["train"].is_null());  // ols estimates no channel noise
  const double model = gc["model"]["train"].get<double>();
  // Noise-free: the estimate is the model's base parameters to 1e-9, the rest the model's.
  EXPECT_NEAR(j["sets"][0]["gc_error"]["train"].get<double>(), model, 1e-6 * model);
  const std::string md = readFile(dir + "/est/floating_identification.md");
  EXPECT_TRUE(contains(md, "| the model's own |")) << md;
  // A horizon under half the 2 ms period: no GC error, said with the flag's spelling.
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --sensors " +
          "torques_contacts --horizon 0.0005 --data " + dir + "/d.csv --out " + dir + "/short");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out,
                       "GC error not measured: --horizon: 0.0005 s is shorter than half a "
                       "sample period (0.002 s)"))
      << r.out;
}

/// identify --method combined refines each set's pc estimate with the GC error of the data's
/// motion: the console, floating_identification.json's `combined` and the report say how it went.
TEST(Cli, IdentifyAFloatingBaseByTheCombinedEstimator) {
  const std::string dir = test::tempPath("floating-combined");
  std::filesystem::create_directories(dir);
  Result r = run("simulate --robot " + kAnymal + " --floating-base --trajectory " +
                 std::string(DYNID_SOURCE_DIR) +
                 "/tests/data/floating/fixtures/anymal_excitation.json --samples 2000 "
                 "--noise-tau 0.05 --noise-force 0.2 --noise-moment 0.05 --out " +
                 dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("identify --robot " + kAnymal + " --floating-base --method combined --sensors " +
          "torques_contacts --horizon 0.02 --segments 10 --combined-iterations 3 --threads 2 "
          "--data " +
          dir + "/d.csv --out " + dir + "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "combined from pc's: GC error ")) << r.out;
  // torques_contacts alone estimates no force's noise: no floor, said in the flag's spelling.
  EXPECT_TRUE(contains(r.err, "no noise floor for the GC term")) << r.err;
  EXPECT_TRUE(contains(r.err, "add torques_wrenches to --sensors")) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/est/floating_identification.json"));
  EXPECT_EQ(j["schema_version"], 4);
  EXPECT_EQ(j["method"], "combined");
  const auto& c = j["sets"][0]["combined"];
  ASSERT_TRUE(c.is_object()) << j["sets"][0];
  EXPECT_LE(c["iterations"].get<int>(), 3);
  EXPECT_LE(c["final_gc"].get<double>(), c["initial_gc"].get<double>());
  EXPECT_EQ(c["gc_weight"], 1.0);
  // The GC error the summary reports is the combined estimate's own.
  EXPECT_EQ(j["sets"][0]["gc_error"]["train"], c["final_gc"]);
  EXPECT_TRUE(contains(readFile(dir + "/est/floating_identification.md"), "combined from pc's"));
}

/// simulate --stance generates a standing sway (the feet still, the legs following) and simulates
/// along it; standing alone leaves combinations the sets cannot determine, which identify says.
TEST(Cli, SimulateAStandingRobotsSway) {
  const std::string dir = test::tempPath("floating-standing");
  std::filesystem::create_directories(dir);
  Result r =
      run("simulate --robot " + kAnymal + " --floating-base --contacts " +
          "LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT --stance 0,0.5,-1,0,0.5,-1,0,-0.5,1,0,-0.5,1 " +
          "--sway 0.02 --turn 0.05 --samples 400 --friction-cone 0.6 --out " + dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "400 states of the motion of a standing sway over the stance"))
      << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;  // every sample within the cones: no warning
  r = run("identify --robot " + kAnymal + " --floating-base --method ols --segments 5 --data " +
          dir + "/d.csv --out " + dir + "/est");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(
      contains(r.out, "torques_wrenches: not estimated: the samples determine 91 of the 94"))
      << r.out;
}

/// Friction cones under ANYmal's feet: the console says how many states were drawn to keep the
/// samples the cones hold.
TEST(Cli, SimulateAFloatingBaseWithinFrictionCones) {
  const std::string dir = test::tempPath("floating-cones");
  std::filesystem::create_directories(dir);
  const Result r = run("simulate --robot " + kAnymal +
                       " --floating-base --contacts LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT --samples 50 "
                       "--friction-cone 0.6 --out " +
                       dir + "/d.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "within friction cones of mu 0.6: ")) << r.out;
  EXPECT_TRUE(contains(r.out, "states drawn")) << r.out;
  // A humanoid on flat soles: their centres of pressure kept in 0.2 x 0.1 m.
  const Result soles = run("simulate --robot " + kRomeo +
                           " --floating-base --contacts l_sole:frame,r_sole:frame --samples 3 "
                           "--friction-cone 0.8 --sole 0.2,0.1 --out " +
                           dir + "/soles.csv");
  ASSERT_EQ(soles.code, 0) << soles.err;
  EXPECT_TRUE(
      contains(soles.out,
               "every frame contact on a sole of 0.2 x 0.1 m: its wrench that of 4 corner forces"))
      << soles.out;
  // A foot's outline, its ankle frame 5 cm from the heel: the corners said back.
  const Result outline =
      run("simulate --robot " + kRomeo +
          " --floating-base --contacts l_sole:frame,r_sole:frame --samples 2 "
          "--friction-cone 0.8 --sole -0.05,-0.05,0.15,-0.05,0.19,0,0.15,0.05,-0.05,0.05 --out " +
          dir + "/outline.csv");
  ASSERT_EQ(outline.code, 0) << outline.err;
  EXPECT_TRUE(contains(outline.out,
                       "on a sole of 5 corners (-0.05, -0.05), (0.15, -0.05), (0.19, 0), "
                       "(0.15, 0.05), (-0.05, 0.05) m: its wrench that of 5 corner forces"))
      << outline.out;
  // The first dataset's motion simulated again within cones too narrow for some of its states.
  const Result along = run("simulate --robot " + kAnymal + " --floating-base --motion-from " + dir +
                           "/d.csv --friction-cone 0.3 --out " + dir + "/again.csv");
  ASSERT_EQ(along.code, 0) << along.err;
  EXPECT_TRUE(contains(along.out, "50 states of the motion of " + dir + "/d.csv")) << along.out;
  EXPECT_TRUE(contains(along.err, "need a contact to pull or slide")) << along.err;
  EXPECT_TRUE(contains(along.err, "dynid simulate: warning: ")) << along.err;
  EXPECT_TRUE(contains(along.err, "of the motion's samples (from t = ")) << along.err;
}

}  // namespace
}  // namespace dynid
