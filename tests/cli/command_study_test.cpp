// dynid study: every method on a dataset, torque fit and GC error side by side, and its errors.
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "data/robots.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, StudyComparesEveryMethodOnTheUsersData) {
  const std::string train = test::tempPath("study_train.csv"),
                    held = test::tempPath("study_held.csv"), dir = test::tempPath("study");
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 2 --noise-tau 0.05 --seed 2 --out " + train).code,
      0);
  ASSERT_EQ(run("simulate --robot puma560 --duration 1 --controller fourier --amplitude 0.6 "
                "--seed 3 --out " +
                held)
                .code,
            0);
  const std::string common = "study --robot puma560 --data " + train + " --validate " + held +
                             " --segments 10 --search-evaluations 60 --refine-iterations 2 ";
  const Result r = run(common + "--methods ols,pc,ga,ga_refined --threads 1 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // Noise-free held-out data from the input model itself: it is the best at both, but the PUMA's
  // massless first link is not physically consistent, so pc is recommended.
  EXPECT_TRUE(contains(r.out, "Use pc for simulation and for control")) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "model fits the held-out torques and predicts the held-out motion "
                       "best"))
      << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/study.json"));
  EXPECT_EQ(j["schema_version"], 5);
  EXPECT_TRUE(j["front"]["points"].empty());  // no --front
  EXPECT_EQ(j["choice"]["key"], "pc");        // the only consistent row with finite errors
  EXPECT_EQ(j["provenance"]["command"][1], "study");
  EXPECT_EQ(j["model"]["name"], "puma560");  // the robot studied, embedded
  EXPECT_EQ(j["order"],
            (std::vector<std::string>{"model", "start", "ols", "pc", "ga", "ga_refined"}));
  for (const char* key : {"torque_relative_error_train", "torque_relative_error_test",
                          "gc_error_train", "gc_error_test", "physically_consistent"})
    EXPECT_TRUE(j["methods"]["ga"].contains(key)) << key;
  // The GA finishes the generation in which the budget runs out.
  EXPECT_GE(j["methods"]["ga"]["evaluations"].get<long>(), 60);
  for (const char* file : {"report.md", "report.html", "torque_vs_gc.svg"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + file)) << file;
  // The same seed, two threads: the same table.
  const std::string dir2 = test::tempPath("study2");
  ASSERT_EQ(run(common + "--methods ols,pc,ga,ga_refined --threads 2 --out " + dir2).code, 0);
  const auto j2 = nlohmann::json::parse(readFile(dir2 + "/study.json"));
  EXPECT_EQ(j2["methods"]["ga_refined"]["gc_error_test"],
            j["methods"]["ga_refined"]["gc_error_test"]);

  // Usage errors (exit 2): an unknown or repeated method, no budget, no held-out data.
  const std::string none = test::tempPath("never_studied");
  EXPECT_EQ(run(common + "--methods ols,lasso --out " + none).code, 2);
  EXPECT_EQ(run(common + "--methods ols,ols --out " + none).code, 2);
  EXPECT_EQ(run("study --robot puma560 --data " + train + " --validate " + held +
                " --search-seconds 0 --out " + none)
                .code,
            2);
  EXPECT_EQ(run("study --robot puma560 --data " + train + " --out " + none).code, 2);
  // Data errors (exit 1): a missing file named, data of another robot.
  const Result missing = run("study --robot puma560 --data " + train + " --validate " +
                             test::tempPath("nope.csv") + " --out " + none);
  EXPECT_EQ(missing.code, 1);
  EXPECT_TRUE(contains(missing.err, "nope.csv")) << missing.err;
  EXPECT_EQ(
      run("study --robot panda --data " + train + " --validate " + held + " --out " + none).code,
      1);
  EXPECT_FALSE(std::filesystem::exists(none));
}

// The report's next step on a URDF whose path holds a space and a quote: one shell word each, and
// the write-back into the identify run's own --out.
TEST(Cli, StudyNextStepQuotesTheRobotPathAsOneShellWord) {
  namespace fs = std::filesystem;
  const std::string dir = test::tempPath("study quote");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string urdf = dir + "/bob's arm.urdf", train = dir + "/t.csv", held = dir + "/h.csv";
  const auto word = [](const std::string& text) {  // for the test's own shell
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  };
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + word(urdf)).code, 0);
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 1.5 --noise-tau 0.1 --out " + word(train)).code, 0);
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 1 --noise-tau 0.1 --seed 2 --out " + word(held))
          .code,
      0);
  const Result r = run("study --robot " + word(urdf) + " --data " + word(train) + " --validate " +
                       word(held) + " --methods pc --segments 6 --out " + word(dir + "/s"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string report = readFile(dir + "/s/report.md");
  EXPECT_TRUE(contains(report, "`dynid identify --method pc --robot '" + dir +
                                   "/bob'\\''s arm.urdf' --drive-terms none --data '" + train +
                                   "' --validate '" + held +
                                   "' --out pc --write-urdf pc/identified.urdf` writes it into a "
                                   "copy of the URDF"))
      << report;
  // With a front, --write-urdf writes the chosen estimate into a copy of the URDF (and its
  // .dynid.json): the same parameters as chosen.json.
  const Result front =
      run("study --robot " + word(urdf) + " --data " + word(train) + " --validate " + word(held) +
          " --methods pc --front-weights 1 --segments 6 --refine-iterations 2 "
          "--write-urdf " +
          word(dir + "/f/chosen.urdf") + " --out " + word(dir + "/f"));
  ASSERT_EQ(front.code, 0) << front.err;
  EXPECT_TRUE(contains(front.out, "wrote " + dir + "/f/chosen.urdf")) << front.out;
  const Model written = loadRobot(dir + "/f/chosen.dynid.json");
  const Model chosen = loadRobot(dir + "/f/chosen.json");
  EXPECT_EQ(written.standardParameters(), chosen.standardParameters());
  // Without a front there is no chosen estimate to write: refused before any work.
  const Result refused =
      run("study --robot " + word(urdf) + " --data " + word(train) + " --validate " + word(held) +
          " --methods pc --write-urdf " + word(dir + "/g/x.urdf") + " --out " + word(dir + "/g"));
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(contains(refused.err, "add --front")) << refused.err;
}

// --front: the combined estimator at each weight, every point measured and consistent, and the
// estimate chosen by the stated rule written as the study's recommendation.
TEST(Cli, StudyFrontSweepsTheCombinedWeightAndChoosesOneEstimate) {
  const auto [train, held] = test::noisyPumaPair("front");
  ASSERT_FALSE(train.empty());
  const std::string dir = test::tempPath("front_study");
  const std::string common = "study --robot puma560 --drive-terms fv,fc --data " + train +
                             " --validate " + held +
                             " --segments 8 --refine-iterations 3 --methods pc,combined ";
  const Result r = run(common + "--front-weights 0.3,3 --threads 2 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "front w=0.3")) << r.out;
  EXPECT_TRUE(contains(r.out, "Chosen: ")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/study.json"));
  ASSERT_EQ(j["front"]["points"].size(), 2u);
  for (const auto& p : j["front"]["points"]) EXPECT_TRUE(p["physically_consistent"].get<bool>());
  EXPECT_EQ(j["front"]["points"][1]["weight"], 3.0);
  EXPECT_EQ(j["front"]["tolerance"], 0.05);
  ASSERT_FALSE(j["choice"]["key"].is_null());
  // The chosen one's held-out torque error is within the bound the rule states.
  const std::string key = j["choice"]["key"];
  const auto chosen = key == "front"
                          ? j["front"]["points"][j["choice"]["front_weight"] == 0.3 ? 0 : 1]
                          : j["methods"][key];
  EXPECT_LE(chosen["torque_relative_error_test"].get<double>(),
            j["choice"]["torque_bound"].get<double>());
  const std::string report = readFile(dir + "/report.md");
  EXPECT_TRUE(contains(report, "## The front")) << report;
  EXPECT_TRUE(contains(report, "Chosen: ")) << report;
  // The next step is the identify command that repeats the choice, spelt by the CLI.
  const std::string repeat = "dynid identify --method " +
                             std::string(key == "front" ? "combined" : key) +
                             " --robot puma560 --drive-terms fv,fc --data " + train;
  EXPECT_TRUE(contains(report, repeat)) << report;
  if (key == "front") {
    EXPECT_TRUE(contains(report, "--front-weights 0.3,3")) << report;
    EXPECT_EQ(j["choice"]["estimate"], "chosen.json");
    // chosen.json is the chosen estimate as a model: predict takes it as its robot, and its
    // held-out torque error is the study's for that point.
    const std::string predicted = test::tempPath("front_predict");
    const Result p =
        run("predict --robot " + dir + "/chosen.json --data " + held + " --out " + predicted);
    ASSERT_EQ(p.code, 0) << p.err;
    const auto prediction = nlohmann::json::parse(readFile(predicted + "/prediction.json"));
    // The same model on the same samples; the study measured it with the training data's rest
    // velocities, predict with the held-out data's: 1 % relative.
    EXPECT_NEAR(prediction["relative_error"].get<double>(),
                chosen["torque_relative_error_test"].get<double>(),
                0.01 * chosen["torque_relative_error_test"].get<double>());
  }
  // Weights that are not a sweep: refused before any work, the option named.
  const std::string none = test::tempPath("front_never");
  const Result bad = run(common + "--front-weights 1,0.5 --out " + none);
  EXPECT_NE(bad.code, 0);
  EXPECT_TRUE(contains(bad.err, "--front-weights")) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(none));
}

}  // namespace
}  // namespace dynid
