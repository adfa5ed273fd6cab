#include "data/json_number.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace dynid {
namespace {

TEST(JsonNumber, NonFiniteNumbersAreNullAndReadBackAsNan) {
  const Eigen::Vector3d v(1.5, std::numeric_limits<double>::infinity(), std::nan(""));
  const nlohmann::json j = numbersOrNull(v);
  EXPECT_EQ(jsonText(j), "[1.5,null,null]");
  EXPECT_EQ(numberOrNan(j[0]), 1.5);
  EXPECT_TRUE(std::isnan(numberOrNan(j[1])));
}

TEST(JsonNumber, TextThatIsNotUtf8IsReplacedNotFatal) {
  // A path in Latin-1 ("daten_\xe4.csv"): nlohmann's default dump throws type_error 316.
  const nlohmann::json j = {{"data", "daten_\xe4.csv"}};
  EXPECT_THROW((void)j.dump(), nlohmann::json::type_error);
  EXPECT_EQ(jsonText(j), "{\"data\":\"daten_\xEF\xBF\xBD.csv\"}");  // U+FFFD
  EXPECT_EQ(jsonText(j, 1), "{\n \"data\": \"daten_\xEF\xBF\xBD.csv\"\n}");
  EXPECT_EQ(nlohmann::json::parse(jsonText(j))["data"], "daten_\uFFFD.csv");
}

}  // namespace
}  // namespace dynid
