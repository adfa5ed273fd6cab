// A document's provenance: written and read back, stamped on a document only while a run is
// current, and the rerun comparison that leaves out exactly the times and the output folder.
#include "analysis/records/provenance.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

using json = nlohmann::json;

RunProvenance sampleRun() {
  RunProvenance run;
  run.interface = "cli";
  run.version = "0.2.0";
  run.commit = "0123456789ab";
  run.command = {"dynid", "search", "--data", "train.csv", "--out", "first"};
  run.working_directory = "/work";
  run.inputs = {{"train.csv", std::string(64, 'a')}, {"-", ""}};
  run.seed = 7;
  run.threads = 2;
  run.started = "2026-12-02T17:00:00Z";
  run.seconds = 1.5;
  return run;
}

/// A search document of `run`, with its own times.
json searchDocument(const RunProvenance& run, double seconds) {
  json d = {{"schema_version", 3},
            {"kind", "dynid.search"},
            {"final_gc_error", 0.25},
            {"seconds", seconds},
            {"history", {{{"iteration", 1}, {"seconds", seconds / 2}}, {{"iteration", 2}}}}};
  d["provenance"] = provenanceJson(run, "dynid.search");
  return d;
}

TEST(Provenance, ReadsBackWhatItWrites) {
  const RunProvenance run = sampleRun();
  const json d = searchDocument(run, 2.0);
  const RunProvenance back = provenanceFrom(d, "search.json");
  EXPECT_EQ(back.command, run.command);
  EXPECT_EQ(back.working_directory, run.working_directory);
  ASSERT_EQ(back.inputs.size(), 2u);
  EXPECT_EQ(back.inputs[0].sha256, run.inputs[0].sha256);
  EXPECT_TRUE(d["provenance"]["inputs"][1]["sha256"].is_null());  // a stream: no content
  EXPECT_EQ(back.seed, run.seed);
  EXPECT_EQ(back.threads, run.threads);
  EXPECT_EQ(back.seconds, run.seconds);
  EXPECT_EQ(d["provenance"]["time_fields"], json({"/seconds", "/history/*/seconds"}));
  json broken = d;
  broken["provenance"]["threads"] = "two";
  EXPECT_THROW(provenanceFrom(broken, "search.json"), ParseError);
  broken.erase("provenance");
  EXPECT_THROW(provenanceFrom(broken, "search.json"), ParseError);
}

TEST(Provenance, StampsDocumentsOnlyWhileARunIsCurrent) {
  const json bare = {{"schema_version", 1}, {"kind", "dynid.thing"}};
  EXPECT_EQ(withProvenance(bare), bare);  // a library caller that began no run
  RunProvenance run = sampleRun();
  run.inputs.clear();
  beginRun(run);
  noteRunSeed(11);
  noteRunThreads(3);
  const json stamped = withProvenance(bare);
  ASSERT_TRUE(stamped.contains("provenance"));
  EXPECT_EQ(stamped["provenance"]["seed"], 11);
  EXPECT_EQ(stamped["provenance"]["threads"], 3);
  EXPECT_EQ(stamped["provenance"]["started"].get<std::string>().size(), 20u);  // ...T..:..:..Z
  EXPECT_EQ(withProvenance(json::array()), json::array());  // not a document: left alone
}

TEST(Provenance, ARerunDiffersOnlyInItsTimesAndOutputFolder) {
  RunProvenance first = sampleRun(), second = sampleRun();
  second.command.back() = "/elsewhere/second";
  second.started = "2026-12-03T09:30:00Z";
  second.seconds = 4.0;
  const json a = searchDocument(first, 2.0);
  json b = searchDocument(second, 3.0);
  EXPECT_TRUE(rerunDifferences(a, b, {"--out"}).empty());
  // "--out=DIR" is the same option.
  first.command.back() = "--out=first";
  first.command.erase(first.command.end() - 2);
  second.command.back() = "--out=/elsewhere/second";
  second.command.erase(second.command.end() - 2);
  EXPECT_TRUE(
      rerunDifferences(searchDocument(first, 1.0), searchDocument(second, 9.0), {"--out"}).empty());
  // A number that changed, and another option: named with both values.
  b["final_gc_error"] = 0.5;
  b["provenance"]["command"][3] = "other.csv";
  const std::vector<std::string> d = rerunDifferences(a, b, {"--out"});
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0], "/final_gc_error: 0.25 -> 0.5");
  EXPECT_EQ(d[1], "/provenance/command/3: \"train.csv\" -> \"other.csv\"");
  // A field the time fields do not name is compared, though it holds seconds.
  json c = searchDocument(sampleRun(), 2.0);
  c["history"][1]["elapsed"] = 1.0;
  EXPECT_EQ(rerunDifferences(a, c, {"--out"}).size(), 1u);
}

TEST(Provenance, EachKindNamesItsTimeFields) {
  EXPECT_EQ(timeFieldsOf("dynid.refine"),
            (std::vector<std::string>{"/seconds", "/cost_history/*/seconds"}));
  EXPECT_EQ(timeFieldsOf("dynid.study"), (std::vector<std::string>{"/seconds", "/methods/*/seconds",
                                                                   "/front/points/*/seconds"}));
  EXPECT_TRUE(timeFieldsOf("dynid.payload").empty());
  // A study's methods are an object: "*" steps through its members too.
  RunProvenance run = sampleRun();
  json a = {{"kind", "dynid.study"},
            {"seconds", 1.0},
            {"methods", {{"ols", {{"seconds", 0.1}, {"gc", 2.0}}}, {"pc", {{"seconds", 0.2}}}}}};
  a["provenance"] = provenanceJson(run, "dynid.study");
  json b = a;
  b["seconds"] = 5.0;
  b["methods"]["ols"]["seconds"] = 0.3;
  b["methods"]["pc"]["seconds"] = 0.4;
  EXPECT_TRUE(rerunDifferences(a, b, {"--out"}).empty());
  b["methods"]["ols"]["gc"] = 3.0;
  EXPECT_EQ(rerunDifferences(a, b, {"--out"}),
            std::vector<std::string>{"/methods/ols/gc: 2.0 -> 3.0"});
}

}  // namespace
}  // namespace dynid
