// dynid payload: a payload identified through the executable, exported, written into a URDF,
// and the refusals.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/rnea.hpp"
#include "data/io.hpp"
#include "data/puma560.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/payload_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

const char* kFlange = " --tool-xyz 0,0,0.05 --tool-rpy 0,0,0.7853981633974483";

TEST(Cli, PayloadFromOneLogAndFromALoadedUnloadedPair) {
  const Model arm = makePuma560(false);
  const Trajectory motion = test::payloadMotion(arm, 8.0, 200.0);
  const std::string loaded = test::payloadLog(
      test::withPayload(arm, 5, test::pumaFlange(), test::toolBody()), motion, "cli_loaded.csv");
  const std::string unloaded = test::payloadLog(arm, motion, "cli_unloaded.csv");
  const std::string out = test::tempPath("cli_payload");
  const Result r = run("payload --arm puma560 --data " + loaded + kFlange +
                       " --format ur,kuka --format abb --format franka,json --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "Mass 1.2 ± ")) << r.out;
  const auto j = nlohmann::json::parse(readFile(out + "/payload.json"));
  EXPECT_EQ(j["kind"], "dynid.payload");
  EXPECT_EQ(j["mode"], "single");
  EXPECT_EQ(j["link"], "link6");
  // Noise-free torques through a 17-digit CSV: the tool to 1e-8.
  EXPECT_NEAR(j["mass"].get<double>(), 1.2, 1e-8);
  EXPECT_NEAR(j["com"][2].get<double>(), 0.08, 1e-8);
  for (const char* file : {"payload.urscript", "payload.kuka.dat", "payload.abb.mod",
                           "payload.franka.json", "payload.body.json", "report.md", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  EXPECT_TRUE(
      test::opensWithVerdict(readFile(out + "/report.html"),
                             {"Estimated", "How well", "Not determined", "Torque source", "Next"}));
  // The pair: the difference, and the body read back as a prior.
  const std::string pair = test::tempPath("cli_payload_pair");
  const Result d = run("payload --arm puma560 --data " + loaded + " --unloaded " + unloaded +
                       kFlange + " --prior " + out + "/payload.body.json --out " + pair);
  ASSERT_EQ(d.code, 0) << d.err;
  const auto k = nlohmann::json::parse(readFile(pair + "/payload.json"));
  EXPECT_EQ(k["mode"], "difference");
  EXPECT_TRUE(k["prior"]["given"].get<bool>());
  EXPECT_NEAR(k["mass"].get<double>(), 1.2, 1e-8);
  EXPECT_NEAR(k["alignment"]["shift"].get<double>(), 0.0, 1e-12);
}

TEST(Cli, PayloadWrittenIntoTheArmsUrdfReloadsAsTheLoadedArm) {
  const Model arm = makePuma560(false);
  const std::string urdf = test::tempPath("cli_payload_arm.urdf");
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
  const Model loaded_arm = test::withPayload(arm, 5, test::pumaFlange(), test::toolBody());
  const std::string loaded =
      test::payloadLog(loaded_arm, test::payloadMotion(arm, 8.0, 200.0), "cli_urdf_loaded.csv");
  const std::string out = test::tempPath("cli_payload_urdf"),
                    written = test::tempPath("cli_payload_written.urdf");
  const Result r = run("payload --arm " + urdf + " --data " + loaded + kFlange + " --write-urdf " +
                       written + " --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  // The written URDF is the loaded arm: its model's link 6 (the payload merged into it by the fixed
  // joint) carries the same inertia as the arm that made the log, to the URDF's shortest decimals.
  const Result show = run("dynamics --robot " + written +
                          " --q 0.1,0.2,0.3,0.4,0.5,0.6 --dq 0.3,0.2,0.1,0.4,0.5,0.6 --ddq "
                          "1,1,1,1,1,1 --json");
  ASSERT_EQ(show.code, 0) << show.err;
  Data data(loaded_arm);
  Eigen::VectorXd q(6), dq(6), ddq(6);
  q << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6;
  dq << 0.3, 0.2, 0.1, 0.4, 0.5, 0.6;
  ddq.setOnes();
  const Eigen::VectorXd tau = rnea(loaded_arm, data, q, dq, ddq);
  const auto d = nlohmann::json::parse(show.out);
  ASSERT_EQ(d["tau"].size(), 6u) << show.out;
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(d["tau"][j].get<double>(), tau[j], 1e-7 * tau.norm()) << j;
}

// docs/PAYLOAD.md's recipe for a simulated loaded/unloaded pair, as written there but with a
// cheaper excitation design (2 starts of 300 evaluations instead of 16 of 2000) and 8 s runs: the
// body attached by `model attach`, both runs under the arm's controller at 20 Hz, the payload back.
TEST(Cli, AttachedBodyPairRecoversIt) {
  const std::string dir = test::tempPath("cli_attach_pair");
  std::filesystem::create_directories(dir);
  const auto step = [&](const std::string& args) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    return r;
  };
  step(
      "model attach --robot panda --drive-terms fv,fc,fo --mass 1.0 --com 0.02,-0.01,0.05 "
      "--inertia 0.004,0,0,0.005,0,0.003 --tool-xyz 0,0,0.107 --out " +
      dir + "/loaded.json");
  step("excite --robot panda --payload --starts 2 --evaluations 300 --period 8 --out " + dir +
       "/excite");
  const std::string sim = " --drive-terms fv,fc,fo --trajectory " + dir +
                          "/excite/excitation.json --duration 8 --bandwidth 20 --noise-tau 0.05";
  const Result loaded = step("simulate --robot " + dir + "/loaded.json --controller-robot panda" +
                             sim + " --seed 2 --out " + dir + "/loaded.csv");
  EXPECT_FALSE(contains(loaded.out + loaded.err, "warning")) << loaded.out << loaded.err;
  step("simulate --robot panda" + sim + " --seed 3 --out " + dir + "/unloaded.csv");
  step("identify --method ols --robot panda --drive-terms fv,fc,fo --data " + dir +
       "/unloaded.csv --out " + dir + "/est");
  step("payload --arm " + dir + "/est/estimate.json --data " + dir + "/loaded.csv --unloaded " +
       dir + "/unloaded.csv --tool-xyz 0,0,0.107 --out " + dir + "/payload");
  const auto p = nlohmann::json::parse(readFile(dir + "/payload/payload.json"));
  // 0.05 N m noise on 8 s: the mass to a thousandth, the centre of mass to a millimetre.
  EXPECT_NEAR(p["mass"].get<double>(), 1.0, 1e-3);
  const std::vector<double> com = {0.02, -0.01, 0.05};
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(p["com"][k].get<double>(), com[k], 1e-3) << k;
  // At the default 5 Hz the loaded run tracks its reference far off, and simulate says to raise
  // the bandwidth; a body no rigid body can be is refused with its moments.
  const Result loose = run("simulate --robot " + dir + "/loaded.json --controller-robot panda " +
                           "--drive-terms fv,fc,fo --trajectory " + dir +
                           "/excite/excitation.json --duration 8 --out " + dir + "/loose.csv");
  EXPECT_TRUE(contains(loose.out + loose.err, "raise --bandwidth")) << loose.out << loose.err;
  const Result bad =
      run("model attach --robot panda --mass 1 --inertia 0.01,0,0,0.001,0,0.001 "
          "--out " +
          dir + "/bad.json");
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(contains(bad.err, "--inertia has principal moments")) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.json"));
}

TEST(Cli, PayloadRefusesWhatItCannotUseAndWritesNothing) {
  const Model arm = makePuma560(false);
  const Trajectory motion = test::payloadMotion(arm, 4.0, 200.0);
  const std::string loaded = test::payloadLog(arm, motion, "cli_refuse_loaded.csv");
  const std::string never = test::tempPath("cli_payload_never");
  Result r = run("payload --arm puma560 --data " + loaded + " --link wrist --out " + never);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "'wrist'")) << r.err;
  r = run("payload --arm puma560 --data " + loaded + " --unloaded " + loaded +
          " --payload-mass 0 --out " + never);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--payload-mass")) << r.err;
  r = run("payload --arm puma560 --data " + loaded + " --payload-mass 1 --out " + never);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--unloaded")) << r.err;
  r = run("payload --arm panda --data " + loaded + " --out " + never);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, loaded)) << r.err;
  Trajectory other = motion;
  other.q *= 1.5;
  const std::string moved = test::payloadLog(arm, other, "cli_refuse_other.csv");
  r = run("payload --arm puma560 --data " + loaded + " --unloaded " + moved + " --out " + never);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "same commanded motion")) << r.err;
  r = run("payload --arm puma560 --data " + loaded + " --format fanuc --out " + never);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "fanuc")) << r.err;
  r = run("payload --arm puma560 --data " + loaded + " --write-urdf x.urdf --out " + never);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--write-urdf")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(never));
}

}  // namespace
}  // namespace dynid
