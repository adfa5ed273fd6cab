// A document's command made ready to run again: its outputs moved into the new folder, its
// inputs checked by content, and the refusals (a stream, a changed input, a Python call).
#include "analysis/records/rerun.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/errors.hpp"
#include "data/digest/sha256.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

namespace fs = std::filesystem;

// The output options of the front end's command lines (the CLI's spelling, as it passes them).
const std::vector<std::string> kOutputs = {"--out", "--checkpoint", "--write-urdf"};

/// A document in a folder of its own, made by `command` in `dir` from `inputs`.
std::string documentOf(const std::string& dir, const std::vector<std::string>& command,
                       const std::vector<InputDigest>& inputs, const std::string& interface) {
  RunProvenance run;
  run.interface = interface;
  run.version = "0.2.0";
  run.commit = "abc";
  run.command = command;
  run.working_directory = dir;
  run.inputs = inputs;
  nlohmann::json d = {{"schema_version", 6}, {"kind", "dynid.estimate"}};
  d["provenance"] = provenanceJson(run, "dynid.estimate");
  static int made = 0;  // each document in a folder of its own
  const std::string folder = dir + "/made" + std::to_string(++made);
  fs::create_directories(folder);
  writeFileAtomically(folder + "/estimate.json", d.dump());
  return folder + "/estimate.json";
}

TEST(Rerun, MovesEveryOutputIntoTheNewFolderAndChecksTheInputs) {
  const std::string dir = test::tempPath("rerun_plan");
  fs::remove_all(dir);
  fs::create_directories(dir);
  writeFileAtomically(dir + "/train.csv", "t\n0\n");
  const std::vector<InputDigest> inputs = {{"train.csv", sha256OfFile(dir + "/train.csv")}};
  const std::string doc = documentOf(
      dir, {"dynid", "identify", "--data", "train.csv", "--out", "made", "--write-urdf=x/arm.urdf"},
      inputs, "cli");
  const RerunPlan plan = planRerun({doc, dir + "/again", "0.2.0", "abc", kOutputs});
  EXPECT_EQ(plan.arguments,
            (std::vector<std::string>{"identify", "--data", "train.csv", "--out", dir + "/again",
                                      "--write-urdf=" + dir + "/again/arm.urdf"}));
  EXPECT_EQ(plan.working_directory, dir);
  EXPECT_EQ(plan.document_name, "estimate.json");
  ASSERT_EQ(plan.notes.size(), 1u);  // the write-back moved; the same dynid
  // Another dynid is noted; the refusals.
  EXPECT_EQ(planRerun({doc, dir + "/again", "0.3.0", "def", kOutputs}).notes.size(), 2u);
  const auto refused = [&](const std::string& file, const std::string& why) {
    try {
      planRerun({file, dir + "/again", "0.2.0", "abc", kOutputs});
      ADD_FAILURE() << why << ": planned";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(documentOf(dir, {"dynid", "monitor", "--data", "-", "--out", "made"}, {}, "cli"),
          "read standard input ('-')");
  refused(documentOf(dir, {"dynid", "monitor", "--data", "s", "--out", "made"}, {{"s", ""}}, "cli"),
          "was read from a stream");
  refused(documentOf(dir, {"dynid.identify", "x.py:3", ""}, {}, "python"), "made by a python call");
  refused(documentOf(dir, {"dynid", "model", "check"}, {}, "cli"), "writes no output folder");
  try {  // a front end that names no output option
    planRerun({doc, dir + "/again", "0.2.0", "abc", {}});
    ADD_FAILURE() << "planned without output options";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("`output_options`"), std::string::npos) << e.what();
  }
  writeFileAtomically(dir + "/train.csv", "t\n1\n");
  refused(doc, "changed since the document was made");
  fs::remove(dir + "/train.csv");
  refused(doc, "is not found");
}

}  // namespace
}  // namespace dynid
