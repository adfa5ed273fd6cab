#include "reports/excitation_report.hpp"

#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "analysis/records/document.hpp"
#include "analysis/records/excitation_record.hpp"
#include "core/errors.hpp"
#include "data/json_number.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

ExciteOutcome smallOutcome(const Model& puma) {
  ExciteRequest r;
  r.robot = puma;
  r.limits = excitationLimits(puma, {});
  r.starts = 1;
  r.evaluations = 30;
  r.check_rate = 100.0;
  r.gc_segments = 10;
  return exciteRun(r);
}

TEST(ExcitationReport, TheJsonRecordsTheDesignBothScoresAndTheLimitsUsed) {
  const Model puma = makePuma560(false);
  const ExciteOutcome o = smallOutcome(puma);
  const nlohmann::json j = excitationJson(puma, {"puma560", 5, 1, 30, 10.0, 100.0}, o);
  EXPECT_EQ(j["schema_version"], kExcitationDocument.schema_version);
  EXPECT_EQ(j["design"]["offset"].size(), 6u);
  EXPECT_EQ(j["design"]["b"][5].size(), 5u);
  EXPECT_EQ(j["design"]["a"][2][4].get<double>(), o.design.a(2, 4));
  EXPECT_TRUE(j["limits"]["floor"].is_null());       // none given
  EXPECT_TRUE(j["limits"]["tau_max"][0].is_null());  // no torque limit: +inf written as null
  EXPECT_EQ(j["limits"]["notes"].size(), 3u);
  EXPECT_EQ(j["designed"]["relative_std_percent"].size(), 36u);
  EXPECT_EQ(j["default_sinusoid"]["samples"], 1001);
  EXPECT_EQ(j["optimiser"]["start_criteria"].size(), 1u);
}

TEST(ExcitationReport, TheCsvHasOneRowPerSampleAndEveryColumn) {
  const Model puma = makePuma560(false);
  const ExciteOutcome o = smallOutcome(puma);
  std::istringstream csv(excitationCsv(puma, o.design, 20.0));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "t,q1,q2,q3,q4,q5,q6,dq1,dq2,dq3,dq4,dq5,dq6,ddq1,ddq2,ddq3,ddq4,ddq5,ddq6");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 201);  // 10 s at 20 Hz, both ends
  std::vector<std::string> missing;
  const Document doc = excitationDocument(puma, {"puma560", 5, 1, 30, 10.0, 20.0}, o, &missing);
  EXPECT_NE(doc.markdown().find("| joint6 |"), std::string::npos);
}

/// A design with stand orientations (`--stands`): excitation.json's `stand` reads back exactly,
/// the report has its section; without, `stand` is null.
TEST(ExcitationReport, TheStandOrientationsReadBackExactly) {
  const Model puma = makePuma560(false);
  const ExciteOutcome o = smallOutcome(puma);
  ExcitationSettings settings{"puma560", 5, 1, 30, 10.0, 100.0};
  EXPECT_TRUE(excitationJson(puma, settings, o)["stand"].is_null());
  StandDesign stand;
  stand.choice.tilts = {{0.0, 0.0}, {-0.1, 0.3}, {0.2, -0.3}};
  stand.choice.condition_added = {std::numeric_limits<double>::infinity(), 120.0, 99.5};
  stand.choice.condition = 99.5;
  StandSetScore score;
  score.combinations = 80;
  score.determined = 79;
  stand.choice.upright = {score};
  score.determined = 80;
  score.condition = 99.5;
  stand.choice.chosen = {score};
  stand.max_tilt = 0.3;
  stand.grid = 7;
  stand.samples = 200;
  settings.stand = stand;
  const nlohmann::json text = nlohmann::json::parse(jsonText(excitationJson(puma, settings, o), 2));
  EXPECT_EQ(excitationStandTiltsFrom(text, "e.json"), stand.choice.tilts);
  EXPECT_TRUE(text["stand"]["condition_added"][0].is_null());  // upright alone: not full rank
  EXPECT_EQ(text["stand"]["sets"][0]["upright"]["determined"], 79);
  const Document doc = excitationDocument(puma, settings, o, nullptr);
  EXPECT_NE(doc.markdown().find("| wrenches | 80 | 79 of 80 | 80 of 80, condition 99.5 |"),
            std::string::npos)
      << doc.markdown();
}

TEST(ExcitationReport, TheDesignReadsBackExactlyAndStrictly) {
  const Model puma = makePuma560(false);
  const ExciteOutcome o = smallOutcome(puma);
  const nlohmann::json j = excitationJson(puma, {"puma560", 5, 1, 30, 10.0, 100.0}, o);
  const nlohmann::json text = nlohmann::json::parse(jsonText(j, 2));  // through the written text
  const FourierSeries d = excitationDesignFrom(text, "e.json", 6);
  EXPECT_EQ(d.period, o.design.period);
  EXPECT_EQ(d.offset, o.design.offset);
  EXPECT_EQ(d.a, o.design.a);  // shortest round-trip decimal: exact
  EXPECT_EQ(d.b, o.design.b);
  auto expectRefused = [&](nlohmann::json bad, const std::string& field) {
    try {
      excitationDesignFrom(bad, "e.json", 6);
      ADD_FAILURE() << "accepted, expected an error naming " << field;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("e.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  EXPECT_THROW(excitationDesignFrom(text, "e.json", 7), ParseError);  // another joint count
  nlohmann::json bad = text;
  bad["schema_version"] = kExcitationDocument.schema_version + 1;  // a later version: refused
  expectRefused(bad, "schema_version");
  bad = text;
  bad["kind"] = "dynid.model";
  expectRefused(bad, "kind");
  bad = text;
  bad["desing"] = 1;
  expectRefused(bad, "desing");
  bad = text;
  bad["design"]["period"] = -1.0;
  expectRefused(bad, "design.period");
  bad = text;
  bad["design"]["a"][2][1] = "x";
  expectRefused(bad, "design.a[2]");
  bad = text;
  bad["design"]["b"][5].erase(0);
  expectRefused(bad, "design.b[5]");
  bad = text;
  bad["design"]["a"][0][0] = 1e300;
  expectRefused(bad, "design.a[0]");
  bad = text;
  bad["design"].erase("offset");
  expectRefused(bad, "design.offset");
}

}  // namespace
}  // namespace dynid
