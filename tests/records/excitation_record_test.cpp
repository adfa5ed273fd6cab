#include "analysis/records/excitation_record.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"

namespace dynid {
namespace {

/// A two-joint, two-harmonic excitation.json as `dynid excite` writes it (the keys the reader
/// takes; reports/excitation_report_test checks the written document reads back exactly).
nlohmann::json design() {
  nlohmann::json doc = documentHeader(kExcitationDocument);
  doc["robot"] = "two-link";
  doc["design"] = {{"period", 8.0},
                   {"harmonics", 2},
                   {"offset", {0.1, -0.2}},
                   {"a", {{0.5, -0.5}, {0.25, -0.25}}},
                   {"b", {{0.2, -0.1}, {0.0, 0.0}}},
                   {"form", "q = offset + sum ..."}};
  return doc;
}

TEST(ExcitationRecord, ReadsTheDesign) {
  const FourierSeries d = excitationDesignFrom(design(), "e.json", 2);
  EXPECT_EQ(d.period, 8.0);
  EXPECT_EQ(d.harmonics(), 2);
  EXPECT_EQ(d.offset[1], -0.2);
  EXPECT_EQ(d.a(1, 0), 0.25);
  EXPECT_EQ(d.b(0, 1), -0.1);
}

TEST(ExcitationRecord, RefusesOtherDocumentsAndBadFieldsNamingThem) {
  const auto refused = [](const nlohmann::json& doc, int joints, const std::string& field) {
    try {
      excitationDesignFrom(doc, "e.json", joints);
      ADD_FAILURE() << "accepted, expected an error naming " << field;
    } catch (const ParseError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("e.json"), std::string::npos) << what;
      EXPECT_NE(what.find(field), std::string::npos) << what;
    }
  };
  refused(design(), 3, "design.offset");  // another robot's joint count
  nlohmann::json bad = design();
  bad["kind"] = kEstimateDocument.kind;
  refused(bad, 2, "kind");
  bad = design();
  bad["design"]["period"] = -1.0;
  refused(bad, 2, "design.period");
  bad = design();
  bad["design"]["a"][1] = {1.0};
  refused(bad, 2, "design.a[1]");
  bad = design();
  bad["surprise"] = 1;
  refused(bad, 2, "surprise");
}

/// Version 5's stand orientations (`dynid excite --stands`): read as written, none where `stand`
/// is null, or absent in an older version; out of range or malformed, refused naming the entry.
TEST(ExcitationRecord, ReadsTheStandTilts) {
  nlohmann::json doc = design();
  doc["stand"] = {{"tilts", {{0.0, 0.0}, {-0.4, 0.4}}}, {"max_tilt", 0.4}, {"grid", 9}};
  std::vector<Eigen::Vector2d> tilts = excitationStandTiltsFrom(doc, "e.json");
  ASSERT_EQ(tilts.size(), 2u);
  EXPECT_EQ(tilts[1], Eigen::Vector2d(-0.4, 0.4));
  doc["stand"] = nullptr;
  EXPECT_TRUE(excitationStandTiltsFrom(doc, "e.json").empty());
  doc.erase("stand");
  doc["schema_version"] = 4;
  EXPECT_TRUE(excitationStandTiltsFrom(doc, "e.json").empty());
  doc["stand"] = nullptr;  // a key version 4 did not have
  EXPECT_THROW(excitationDesignFrom(doc, "e.json", 2), ParseError);
  const auto refused = [](const nlohmann::json& stand, const std::string& field) {
    nlohmann::json bad = design();
    bad["stand"] = stand;
    try {
      excitationStandTiltsFrom(bad, "e.json");
      ADD_FAILURE() << "accepted, expected an error naming " << field;
    } catch (const ParseError& e) {
      EXPECT_TRUE(std::string(e.what()).find(field) != std::string::npos) << e.what();
    }
  };
  refused({{"tilts", {{0.0, 0.0, 0.0}}}}, "stand.tilts[0]");
  refused({{"tilts", {{0.0, 2.0}}}}, "stand.tilts[0]");
  refused({{"tilts", nlohmann::json::array()}}, "stand.tilts");
  refused({{"tilts", std::vector<std::vector<double>>(17, {0.0, 0.0})}}, "stand.tilts");
  refused({{"max_tilt", 0.4}}, "stand.tilts");
  refused({{"tilts", {{0.0, 0.0}}}, {"yaw", 1}}, "yaw");
  refused(1, "stand");
}

}  // namespace
}  // namespace dynid
