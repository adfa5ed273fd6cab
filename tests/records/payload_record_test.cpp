#include "analysis/records/payload_record.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

nlohmann::json bodyDocument() {
  return {{"schema_version", 1},
          {"kind", "dynid.payload_body"},
          {"standard",
           {{"m", 1.5},
            {"mx", 0.03},
            {"my", 0.0},
            {"mz", 0.09},
            {"Ixx", 0.01},
            {"Ixy", 0.0},
            {"Ixz", 0.0},
            {"Iyy", 0.011},
            {"Iyz", 0.0},
            {"Izz", 0.004}}}};
}

std::string refusal(const nlohmann::json& document) {
  try {
    payloadBodyFrom(document, "prior.json");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(PayloadRecord, ReadsTheBodyOfEitherPayloadDocument) {
  nlohmann::json d = bodyDocument();
  Eigen::Matrix<double, 10, 1> expected;
  expected << 1.5, 0.03, 0.0, 0.09, 0.01, 0.0, 0.0, 0.011, 0.0, 0.004;
  EXPECT_EQ(payloadBodyFrom(d, "prior.json"), expected);
  d["kind"] = "dynid.payload";
  EXPECT_EQ(payloadBodyFrom(d, "prior.json"), expected);
}

TEST(PayloadRecord, RefusalsNameTheFileAndTheField) {
  nlohmann::json d = bodyDocument();
  d["kind"] = "dynid.estimate";
  EXPECT_NE(refusal(d).find("prior.json"), std::string::npos);
  EXPECT_NE(refusal(d).find("kind"), std::string::npos);
  d = bodyDocument();
  d["standard"]["Ixz"] = "0";
  EXPECT_NE(refusal(d).find("standard.Ixz"), std::string::npos);
  d = bodyDocument();
  d.erase("standard");
  EXPECT_NE(refusal(d).find("standard"), std::string::npos);
  EXPECT_NE(refusal(nlohmann::json::array()).find("kind"), std::string::npos);
}

}  // namespace
}  // namespace dynid
