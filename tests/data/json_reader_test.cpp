// data/json_reader: documents parse strictly (duplicate keys, numbers beyond a double) and fields
// are read with their types and ranges, every error naming the file and the JSON path.
#include "data/json_reader.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

/// The ParseError's element for parsing `text`, or "<none>" when it parses.
std::string fault(const std::string& text) {
  try {
    parseJsonDocument(text, "f.json");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "f.json");
    return e.element();
  }
  return "<none>";
}

TEST(JsonReader, DuplicateKeysAndHugeNumbersAreRefused) {
  EXPECT_EQ(fault(R"({"a": 1, "b": {"c": 2}, "d": [{"c": 3}, {"c": 4}]})"), "<none>");
  EXPECT_EQ(fault(R"({"m": 1, "m": 2})"), "m");
  EXPECT_EQ(fault(R"({"a": {"x": 1, "y": 2, "x": 3}})"), "x");
  EXPECT_EQ(fault(R"([{"k": 1}, {"k": 2, "k": 3}])"), "k");
  EXPECT_EQ(fault(R"({"a": 1e400})"), "");  // nlohmann's out_of_range, as a ParseError
  EXPECT_EQ(fault(R"({"a": )"), "");
  // A key is checked within its own object only, whatever the nesting in between.
  EXPECT_EQ(fault(R"({"a": {"a": {"a": 1}}, "b": [[{"a": 1}]]})"), "<none>");
}

TEST(JsonReader, FieldsAreCheckedForTypeAndRange) {
  const JsonReader read("f.json");
  const nlohmann::json doc = parseJsonDocument(
      R"({"schema_version": 1, "n": 5, "x": 2.5, "s": "t", "v": [1, 2], "big": 18446744073709551615})",
      "f.json");
  EXPECT_NO_THROW(read.header(doc, 1, nullptr));
  EXPECT_THROW(read.header(doc, 2, nullptr), ParseError);
  EXPECT_EQ(read.integer(doc, "", "n", 0, 10), 5);
  EXPECT_THROW(read.integer(doc, "", "n", 6, 10), ParseError);
  EXPECT_THROW(read.integer(doc, "", "big", 0, 10), ParseError);  // beyond long long
  EXPECT_THROW(read.integer(doc, "", "x", 0, 10), ParseError);    // not an integer
  EXPECT_EQ(read.number(doc, "", "x", 0.0, 3.0), 2.5);
  EXPECT_THROW(read.number(doc, "", "s"), ParseError);
  EXPECT_EQ(read.vector(doc["v"], "v", 2).size(), 2);
  EXPECT_THROW(read.vector(doc["v"], "v", 3), ParseError);
  try {
    read.onlyKeys(doc, "", {"schema_version", "n", "x", "s", "v"});
    ADD_FAILURE() << "an unknown key passed";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.element(), "big");
  }
}

}  // namespace
}  // namespace dynid
