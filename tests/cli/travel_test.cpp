// Results that travel: an identify output folder moved elsewhere, the URDF it came from deleted,
// and its estimate used from yet another folder by predict, monitor and payload, with the same
// numbers as before the move (estimate.json embeds its robot).
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "data/puma560.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/payload_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;
using test::Result;
using test::run;

/// The numbers each command gives for the estimate at `estimate` (a path as typed from the
/// current folder), from the logs at `logs`.
struct Numbers {
  nlohmann::json prediction, thresholds, payload;
};

Numbers numbersOf(const std::string& estimate, const std::string& logs, const std::string& out) {
  Numbers n;
  const Result p = run("predict --estimate " + estimate + " --data " + logs + "/test.csv --out " +
                       out + "/pred");
  EXPECT_EQ(p.code, 0) << p.err;
  n.prediction = nlohmann::json::parse(readFile(out + "/pred/prediction.json"));
  const Result m = run("monitor --arm " + estimate + " --data " + logs +
                       "/test.csv --calibration " + logs + "/test.csv --out " + out + "/mon");
  EXPECT_EQ(m.code, 0) << m.err;
  n.thresholds = nlohmann::json::parse(readFile(out + "/mon/thresholds.json"));
  const Result l = run("payload --arm " + estimate + " --data " + logs +
                       "/loaded.csv --tool-xyz 0,0,0.05 --tool-rpy 0,0,0.7853981633974483 --out " +
                       out + "/load");
  EXPECT_EQ(l.code, 0) << l.err;
  n.payload = nlohmann::json::parse(readFile(out + "/load/payload.json"));
  return n;
}

TEST(CliTravel, AnEstimateMovedAwayFromItsUrdfGivesTheSameNumbersFromAnotherFolder) {
  const fs::path root = test::tempPath("travel");
  const fs::path made = root / "made", moved = root / "moved", work = root / "work";
  for (const fs::path& d : {made, moved, work}) fs::create_directories(d);
  const std::string urdf = (made / "arm.urdf").string();
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
  ASSERT_EQ(run("simulate --robot puma560 --duration 4 --noise-tau 0.05 --seed 3 --out " +
                (made / "train.csv").string())
                .code,
            0);
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --noise-tau 0.05 --seed 4 --frequency "
                "0.3,0.4,0.5,0.6,0.7,0.8 --out " +
                (made / "test.csv").string())
                .code,
            0);
  const Model arm = makePuma560(false);
  const std::string loaded =
      test::payloadLog(test::withPayload(arm, 5, test::pumaFlange(), test::toolBody()),
                       test::payloadMotion(arm, 6.0, 200.0), "travel_loaded.csv");
  fs::copy_file(loaded, made / "loaded.csv");
  const Result id = run("identify --method ols --robot " + urdf + " --data " +
                        (made / "train.csv").string() + " --out " + (made / "est").string());
  ASSERT_EQ(id.code, 0) << id.err;
  const Numbers before =
      numbersOf((made / "est/estimate.json").string(), made.string(), (root / "before").string());
  // Moved, the URDF gone, used from another folder by relative paths.
  fs::rename(made / "est", moved / "est");
  for (const char* log : {"test.csv", "loaded.csv"}) fs::rename(made / log, moved / log);
  fs::remove(urdf);
  const fs::path here = fs::current_path();
  fs::current_path(work);
  const Numbers after = numbersOf("../moved/est/estimate.json", "../moved", "after");
  fs::current_path(here);
  for (const char* key : {"relative_error", "residual_rms", "band"})
    EXPECT_EQ(after.prediction[key], before.prediction[key]) << key;
  for (const char* key : {"thresholds", "thresholds_at_rest", "moving_regimes"})
    EXPECT_EQ(after.thresholds[key], before.thresholds[key]) << key;
  for (const char* key : {"mass", "com", "inertia_about_com", "standard"})
    EXPECT_EQ(after.payload[key], before.payload[key]) << key;
  EXPECT_FALSE(after.payload["mass"].is_null());
  // The estimate says where its robot came from: the file's name and its SHA-256.
  auto e = nlohmann::json::parse(readFile((moved / "est/estimate.json").string()));
  EXPECT_EQ(e["model_source"]["file"], "arm.urdf");
  EXPECT_EQ(e["model_source"]["sha256"].get<std::string>().size(), 64u);
  // What predict, monitor and payload made from it embeds the same robot and source, so that
  // each of their documents travels too (issue 69, item 1).
  for (const nlohmann::json* doc : {&after.prediction, &after.thresholds, &after.payload}) {
    EXPECT_EQ((*doc)["model_source"], e["model_source"]) << (*doc)["kind"];
    EXPECT_EQ((*doc)["model"]["bodies"].size(), e["model"]["bodies"].size()) << (*doc)["kind"];
  }
  // An older estimate (version 4, no model embedded) whose robot_spec was typed relative to the
  // folder identify ran in: found beside the estimate, from any folder.
  const fs::path old = root / "old";
  fs::create_directories(old);
  ASSERT_EQ(
      run("model export --robot puma560 --format urdf --out " + (old / "arm.urdf").string()).code,
      0);
  e["schema_version"] = 4;
  e.erase("model");
  e.erase("model_source");
  e["robot_spec"] = "arm.urdf";
  writeFileAtomically((old / "estimate.json").string(), e.dump());
  fs::current_path(work);
  const Result p = run("predict --estimate ../old/estimate.json --data ../moved/test.csv --out v4");
  fs::current_path(here);
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_EQ(nlohmann::json::parse(readFile((work / "v4/prediction.json").string()))["residual_rms"],
            before.prediction["residual_rms"]);
}

// An estimate dynid wrote in version 1 (a fuzz seed since 2026-11-24): `dynid upgrade` rewrites
// it in the current version with its robot embedded, and it predicts exactly as the original;
// monitor says when it reads the original as it is.
TEST(CliTravel, AnUpgradedEstimatePredictsAsTheOriginal) {
  const std::string v1 =
      std::string(DYNID_SOURCE_DIR) + "/tests/fuzz/corpus/estimate_json/puma560_ols.json";
  const std::string dir = test::tempPath("upgrade_v1");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Result up = run("upgrade " + v1 + " --out " + dir + "/estimate.json");
  ASSERT_EQ(up.code, 0) << up.err;
  EXPECT_TRUE(test::contains(up.err, "dynid.estimate version 1 -> 8")) << up.err;
  EXPECT_TRUE(test::contains(up.err, "note: embedded the robot it was made for")) << up.err;
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + dir + "/d.csv").code, 0);
  nlohmann::json residuals[2];
  for (int k = 0; k < 2; ++k) {
    const std::string out = dir + "/pred" + std::to_string(k);
    const Result p = run("predict --estimate " + (k == 0 ? v1 : dir + "/estimate.json") +
                         " --data " + dir + "/d.csv --out " + out);
    ASSERT_EQ(p.code, 0) << p.err;
    // predict says when it reads an older estimate as it is, as monitor and payload do.
    EXPECT_EQ(test::contains(p.err, "is dynid.estimate version 1 (current 8): read as it is"),
              k == 0)
        << p.err;
    residuals[k] = nlohmann::json::parse(readFile(out + "/prediction.json"))["residual_rms"];
  }
  EXPECT_EQ(residuals[1], residuals[0]);
  const Result m = run("monitor --arm " + v1 + " --data " + dir + "/d.csv --calibration " + dir +
                       "/d.csv --out " + dir + "/mon");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(test::contains(m.out + m.err,  // among its warnings, on its summary
                             "is dynid.estimate version 1 (current 8): read as it is; "
                             "upgrading the document rewrites it in version 8"))
      << m.out << m.err;
  // The output is a new file, never the document itself; a CSV is no document.
  EXPECT_EQ(run("upgrade " + dir + "/estimate.json --out " + dir + "/estimate.json").code, 2);
  EXPECT_EQ(run("upgrade " + dir + "/d.csv --out " + dir + "/x.json").code, 1);
}

}  // namespace
}  // namespace dynid
