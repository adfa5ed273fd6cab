#include "reports/excitation_report.hpp"

#include <sstream>

#include <gtest/gtest.h>

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
  return exciteRun(r);
}

TEST(ExcitationReport, TheJsonRecordsTheDesignBothScoresAndTheLimitsUsed) {
  const Model puma = makePuma560(false);
  const ExciteOutcome o = smallOutcome(puma);
  const nlohmann::json j = excitationJson(puma, {"puma560", 5, 1, 30, 10.0, 100.0}, o);
  EXPECT_EQ(j["schema_version"], kExcitationSchemaVersion);
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

}  // namespace
}  // namespace dynid
