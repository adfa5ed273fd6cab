#include "analysis/records/excitation_record.hpp"

#include <gtest/gtest.h>

#include <string>

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

}  // namespace
}  // namespace dynid
