// dynid rerun: a document's recorded command run again into a new folder gives the same document
// apart from its times (identify, with its URDF write-back too, a seeded excite, a search with an
// evaluation budget, payload),
// and the refusals: no provenance, its own folder, an input changed since.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/digest/sha256.hpp"
#include "data/io.hpp"
#include "data/puma560.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/payload_logs.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::Result;
using test::run;

/// A fresh folder for one test.
std::string freshDir(const std::string& name) {
  const std::string dir = test::tempPath(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

nlohmann::json documentAt(const std::string& path) { return nlohmann::json::parse(readFile(path)); }

TEST(CliRerun, IdentifyExciteSearchAndPayloadRerunToTheSameDocuments) {
  const std::string dir = freshDir("rerun_same");
  const std::string train = dir + "/train.csv";
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 3 --noise-tau 0.05 --seed 5 --out " + train).code,
      0);
  const Model arm = makePuma560(false);
  const std::string loaded =
      test::payloadLog(test::withPayload(arm, 5, test::pumaFlange(), test::toolBody()),
                       test::payloadMotion(arm, 6.0, 200.0), "rerun_loaded.csv");
  const std::string urdf = dir + "/arm.urdf";
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
  const std::pair<const char*, std::string> commands[] = {
      {"id/estimate.json", "identify --method wls --robot puma560 --data " + train},
      {"ex/excitation.json",
       "excite --robot puma560 --seed 4 --starts 2 --evaluations 150 --threads 2"},
      {"se/search.json", "search --method nlo --robot puma560 --data " + train +
                             " --segments 20 --perturb 0.3 --seed 3 --budget-evals 200"},
      {"wb/estimate.json", "identify --method pc --robot " + urdf + " --data " + train +
                               " --write-urdf " + dir + "/wb/arm_identified.urdf"},
      {"pl/payload.json", "payload --arm puma560 --data " + loaded +
                              " --tool-xyz 0,0,0.05 --tool-rpy 0,0,0.7853981633974483"},
  };
  for (const auto& [document, command] : commands) {
    const std::string folder = fs::path(document).parent_path().string();
    const Result made = run(command + " --out " + dir + "/" + folder);
    ASSERT_EQ(made.code, 0) << command << "\n" << made.err;
    const Result again =
        run("rerun " + dir + "/" + document + " --out " + dir + "/again_" + folder);
    EXPECT_EQ(again.code, 0) << document << "\n" << again.out << again.err;
    EXPECT_TRUE(contains(again.out, "is the same as")) << again.out;
    EXPECT_TRUE(contains(again.err, "rerunning (in ")) << again.err;
  }
  // identify's write-back went into the rerun's folder, by its name; the original stays.
  EXPECT_TRUE(fs::exists(dir + "/again_wb/arm_identified.urdf"));
  EXPECT_EQ(readFile(dir + "/again_wb/arm_identified.urdf"),
            readFile(dir + "/wb/arm_identified.urdf"));
  // What the provenance records: the command as typed, the inputs by content, seed and threads.
  const nlohmann::json p = documentAt(dir + "/id/estimate.json")["provenance"];
  EXPECT_EQ(p["interface"], "cli");
  EXPECT_EQ(p["version"], DYNID_VERSION_TEXT);
  EXPECT_EQ(p["command"][1], "identify");
  EXPECT_EQ(p["command"].back(), dir + "/id");
  EXPECT_EQ(p["working_directory"], fs::current_path().string());
  ASSERT_EQ(p["inputs"].size(), 1u) << p["inputs"];  // the built-in robot is no file
  EXPECT_EQ(p["inputs"][0]["file"], train);
  EXPECT_EQ(p["inputs"][0]["sha256"], sha256OfFile(train));
  EXPECT_EQ(p["seed"], 1);  // the structural rank test's default seed
  EXPECT_GE(p["threads"].get<int>(), 1);
  EXPECT_EQ(documentAt(dir + "/ex/excitation.json")["provenance"]["threads"], 2);
  const nlohmann::json search = documentAt(dir + "/se/search.json")["provenance"];
  EXPECT_EQ(search["seed"], 3);
  EXPECT_EQ(search["time_fields"], nlohmann::json({"/seconds", "/history/*/seconds"}));
  // The rerun's own documents record its command, the output folder the new one.
  EXPECT_EQ(documentAt(dir + "/again_id/estimate.json")["provenance"]["command"].back(),
            dir + "/again_id");
}

TEST(CliRerun, SaysWhatDiffersAndRefusesWhatCannotBeTheSameRun) {
  const std::string dir = freshDir("rerun_refusals");
  const std::string train = dir + "/train.csv";
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --seed 6 --out " + train).code, 0);
  ASSERT_EQ(run("identify --robot puma560 --data " + train + " --out " + dir + "/id").code, 0);
  // A document whose numbers were edited: the rerun names the field and both values, exit 1.
  nlohmann::json edited = documentAt(dir + "/id/estimate.json");
  edited["relative_error"] = 0.5;
  fs::create_directories(dir + "/edited");
  writeFileAtomically(dir + "/edited/estimate.json", edited.dump(2));
  const Result differs = run("rerun " + dir + "/edited/estimate.json --out " + dir + "/r1");
  EXPECT_EQ(differs.code, 1) << differs.err;
  EXPECT_TRUE(contains(differs.out, "differs from")) << differs.out;
  EXPECT_TRUE(contains(differs.out, "/relative_error: 0.5 -> ")) << differs.out;
  // Without --out: the document's folder with -rerun appended.
  const Result beside = run("rerun " + dir + "/id/estimate.json");
  EXPECT_EQ(beside.code, 0) << beside.err;
  EXPECT_TRUE(contains(beside.out, dir + "/id-rerun/estimate.json is the same as")) << beside.out;
  // The document's own folder is no place for the rerun (it is compared with what is there).
  const Result own = run("rerun " + dir + "/id/estimate.json --out " + dir + "/id");
  EXPECT_EQ(own.code, 2) << own.err;
  EXPECT_TRUE(contains(own.err, "the folder the document is in")) << own.err;
  // No provenance (a document of an earlier version): nothing to rerun.
  nlohmann::json old = documentAt(dir + "/id/estimate.json");
  old.erase("provenance");
  old["schema_version"] = 5;
  writeFileAtomically(dir + "/old.json", old.dump());
  const Result none = run("rerun " + dir + "/old.json --out " + dir + "/r2");
  EXPECT_EQ(none.code, 1);
  EXPECT_TRUE(contains(none.err, "provenance: missing")) << none.err;
  // An input changed since: refused before anything runs, both digests named.
  writeFileAtomically(train, readFile(train) + "\n");
  const Result changed = run("rerun " + dir + "/id/estimate.json --out " + dir + "/r3");
  EXPECT_EQ(changed.code, 1);
  EXPECT_TRUE(contains(changed.err, "changed since the document was made")) << changed.err;
  EXPECT_FALSE(fs::exists(dir + "/r3/estimate.json"));
}

}  // namespace
}  // namespace dynid
