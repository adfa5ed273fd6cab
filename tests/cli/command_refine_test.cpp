// dynid refine: from a search.json and from an estimate.json.
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

// A search or an estimate embeds the robot it was made on: refining it on a robot with other
// kinematics (here joint 2's frame moved by 0.1 m) is refused with what differs.
TEST(Cli, RefineRefusesAnotherRobotThanTheStartWasMadeOn) {
  const std::string dir = test::tempPath("refine_other_robot");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string train = dir + "/train.csv", urdf = dir + "/arm.urdf";
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --out " + train).code, 0);
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
  std::string text = readFile(urdf);
  const std::string joint2 = "<origin xyz=\"0 0 0\" rpy=\"1.5707963267948966 -0 0\"/>";
  ASSERT_NE(text.find(joint2), std::string::npos) << text;
  text.replace(text.find(joint2), joint2.size(),
               "<origin xyz=\"0 0 0.1\" rpy=\"1.5707963267948966 -0 0\"/>");
  const std::string moved = dir + "/moved.urdf";
  writeFileAtomically(moved, text);
  ASSERT_EQ(run("search --method nlo --robot " + urdf + " --data " + train +
                " --perturb 0.1 --seed 1 --segments 10 --budget-evals 20 --out " + dir + "/s")
                .code,
            0);
  ASSERT_EQ(run("identify --robot " + urdf + " --data " + train + " --out " + dir + "/e").code, 0);
  for (const std::string& from : {dir + "/s/search.json", dir + "/e/estimate.json"}) {
    const Result r = run("refine --robot " + moved + " --from " + from + " --data " + train +
                         " --max-iterations 1 --out " + dir + "/r");
    EXPECT_EQ(r.code, 1) << from << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "was made on another robot than")) << r.err;
    EXPECT_TRUE(contains(r.err, "link 2 (link2)'s frame at q = 0 lies 0.1 m")) << r.err;
    EXPECT_TRUE(contains(r.err, "(--robot)")) << r.err;  // the request field, as this CLI spells it
  }
  // The robot it was made on is accepted.
  const Result same = run("refine --robot " + urdf + " --from " + dir + "/s/search.json --data " +
                          train + " --max-iterations 1 --out " + dir + "/r");
  EXPECT_EQ(same.code, 0) << same.err;
}

// search.json and refine.json 2 embed the robot (model, model_source); refine --from still reads
// a search.json 1, which has neither.
TEST(Cli, RefineReadsEitherSearchVersionAndBothEmbedTheRobot) {
  const std::string train = test::tempPath("embed_train.csv"), dir = test::tempPath("embed_s");
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --out " + train).code, 0);
  ASSERT_EQ(run("search --method ga --robot puma560 --data " + train +
                " --perturb 0.1 --seed 1 --segments 10 --threads 1 --population 6 "
                "--budget-evals 12 --out " +
                dir)
                .code,
            0);
  auto s = nlohmann::json::parse(readFile(dir + "/search.json"));
  EXPECT_EQ(s["schema_version"], 3);
  EXPECT_EQ(s["model"]["name"], "puma560");
  EXPECT_EQ(s["model_source"]["spec"], "puma560");
  s["schema_version"] = 1;
  s.erase("provenance");
  s.erase("model");
  s.erase("model_source");
  const std::string old = test::tempPath("embed_search_v1.json");
  std::ofstream(old) << s.dump();
  for (const std::string& from : {dir + "/search.json", old}) {
    const std::string out = test::tempPath("embed_refined");
    std::filesystem::remove_all(out);
    const Result r = run("refine --robot puma560 --from " + from + " --data " + train +
                         " --max-iterations 2 --threads 1 --out " + out);
    ASSERT_EQ(r.code, 0) << from << ": " << r.err;
    // The version 1 search is read as it is, and refine says so.
    EXPECT_EQ(contains(r.err, "is dynid.search version 1 (current 3): read as it is"), from == old)
        << r.err;
    const auto j = nlohmann::json::parse(readFile(out + "/refine.json"));
    EXPECT_EQ(j["schema_version"], 3);
    EXPECT_EQ(j["provenance"]["command"][1], "refine");
    EXPECT_EQ(j["model_source"]["spec"], "puma560");
    EXPECT_EQ(j["model"]["bodies"].size(), 6u);  // the PUMA's six links
  }
}

TEST(Cli, RefineFromASearchAndFromAnEstimate) {
  const std::string train = test::tempPath("refine_train.csv"), dir = test::tempPath("refine_s"),
                    refined = test::tempPath("refined");
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --out " + train).code, 0);
  ASSERT_EQ(run("search --method ga --robot puma560 --data " + train +
                " --perturb 0.1 --truth puma560 --seed 1 --segments 10 --threads 2 --population 10 "
                "--budget-evals 20 --out " +
                dir)
                .code,
            0);
  const Result r = run("refine --robot puma560 --from " + dir + "/search.json --data " + train +
                       " --truth puma560 --max-iterations 5 --threads 2 --out " + refined);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(refined + "/refine.json"));
  for (const char* key :
       {"schema_version", "estimate", "cost_history", "termination", "solution_usable",
        "base_parameters", "identifiability", "final_base_parameter_error", "parameters_at_bound"})
    EXPECT_TRUE(j.contains(key)) << key;
  // The search's settings carry over: 10 segments, the same free parameters.
  EXPECT_EQ(j["settings"]["segments"], 10);
  const auto s = nlohmann::json::parse(readFile(dir + "/search.json"));
  EXPECT_EQ(j["settings"]["free_parameters"], s["settings"]["free_parameters"]);
  EXPECT_LT(j["final_gc_error"].get<double>(), j["initial_gc_error"].get<double>());
  EXPECT_EQ(j["base_parameters"]["values"].size(), 36u);
  EXPECT_EQ(j["base_parameters"]["covariance"].size(), 36u);
  EXPECT_FALSE(j["identifiability"]["free_directions"].empty());
  // Both stages' iterations (0 .. N each) are in the history, base coordinates first.
  EXPECT_TRUE(j["base_stage"]["run"].get<bool>());
  EXPECT_EQ(j["cost_history"].size(), j["base_stage"]["iterations"].get<std::size_t>() + 1 +
                                          j["iterations"].get<std::size_t>() + 1);
  EXPECT_EQ(j["cost_history"].front()["stage"], "base");
  EXPECT_EQ(j["cost_history"].back()["stage"], "parameters");
  EXPECT_TRUE(j["base_stage"].contains("base_parameter_error"));
  // From an identify estimate (physically consistent), estimating the starts too.
  const std::string estimate = test::tempPath("pc_estimate");
  const Result pc =
      run("identify --method pc --robot puma560 --data " + train + " --out " + estimate);
  ASSERT_EQ(pc.code, 0) << pc.err;
  const auto e = nlohmann::json::parse(readFile(estimate + "/estimate.json"));
  EXPECT_EQ(e["method"], "pc");
  EXPECT_TRUE(e["physically_consistent"]["solution_usable"].get<bool>());
  const Result from_estimate = run(
      "refine --robot puma560 --from " + estimate + "/estimate.json --data " + train +
      " --segments 10 --estimate-initial-states --max-iterations 3 --threads 2 --out " + refined);
  ASSERT_EQ(from_estimate.code, 0) << from_estimate.err;
  const auto k = nlohmann::json::parse(readFile(refined + "/refine.json"));
  // 10 segments spread over the data, with gaps: independent starts, Schur elimination.
  EXPECT_EQ(k["settings"]["linear_solver"], "SPARSE_SCHUR");
  EXPECT_EQ(k["settings"]["chained_segments"], 0);
  EXPECT_EQ(k["settings"]["continuity_weight"], 10.0);
  EXPECT_TRUE(k.contains("initial_states"));
  // Not a start file: a data error naming the file.
  const Result bad =
      run("refine --robot puma560 --from " + train + " --data " + train + " --out " + refined);
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(contains(bad.err, train)) << bad.err;
  EXPECT_EQ(run("refine --robot puma560 --from x --data y --max-iterations 0 --out d").code, 2);
  EXPECT_EQ(run("refine --robot puma560 --from x --data y --continuity-weight -1 --out d").code, 2);
}

}  // namespace
}  // namespace dynid
