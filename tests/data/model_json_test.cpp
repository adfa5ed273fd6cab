#include "data/model_json.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

void expectSameModel(const Model& a, const Model& b) {
  ASSERT_EQ(a.numJoints(), b.numJoints());
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.gravity(), b.gravity());
  EXPECT_EQ(a.driveTerms(), b.driveTerms());
  EXPECT_EQ(a.parents(), b.parents());
  EXPECT_EQ(a.joint_types(), b.joint_types());
  EXPECT_EQ(a.standardParameters(), b.standardParameters());  // bit for bit
  for (int i = 0; i < a.numJoints(); ++i) {
    EXPECT_EQ(a.joint_placements()[i].rotation, b.joint_placements()[i].rotation);
    EXPECT_EQ(a.joint_placements()[i].translation, b.joint_placements()[i].translation);
    EXPECT_EQ(a.body_placements()[i].rotation, b.body_placements()[i].rotation);
    EXPECT_EQ(a.axes()[i], b.axes()[i]);
    EXPECT_EQ(a.limits[i].upper, b.limits[i].upper);
    for (int k = 0; k < kDriveTermCount; ++k)
      EXPECT_EQ(a.drives()[i].term(k), b.drives()[i].term(k));
  }
}

TEST(ModelJson, RoundTripIsExact) {
  expectSameModel(makePuma560(true), modelFromJson(modelToJson(makePuma560(true)), "p.json"));
  const Model tree = test::randomTree(9, {.drives = true});
  expectSameModel(tree, modelFromJson(modelToJson(tree), "t.json"));
}

void expectError(const std::string& from, const std::string& to, const std::string& fragment) {
  std::string text = modelToJson(makePuma560());
  const std::size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    modelFromJson(text, "robot.json");
    FAIL() << "expected ParseError containing " << fragment;
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), "robot.json");
  }
}

TEST(ModelJson, ErrorsNameTheJsonPath) {
  expectError("\"m\": 17.4", "\"m\": \"heavy\"", "bodies[1].inertial.m: expected a number");
  expectError("\"m\": 17.4", "\"m\": -17.4", "bodies[1].inertial.m: negative mass");
  expectError("\"m\": 17.4", "\"mass\": 17.4", "bodies[1].inertial.mass: unknown key");
  expectError("\"parent\": \"link2\"", "\"parent\": \"link9\"", "bodies[2].parent: unknown parent");
  expectError("\"type\": \"revolute\"", "\"type\": \"floating\"", "bodies[0].joint.type");
  expectError("\"schema_version\": 1", "\"schema_version\": 7", "schema_version: unsupported");
  expectError("\"bodies\": [", "\"bodies\": [[", "invalid JSON");
  // Names go into every output: each unique, none with a control character (found by fuzzing:
  // a DH model with two links of one name loaded, and its exported JSON did not load back).
  expectError("\"name\": \"joint3\"", "\"name\": \"joint2\"",
              "bodies[2].joint.name: duplicate joint name 'joint2'");
  expectError("\"name\": \"link3\"", "\"name\": \"link\\u00013\"",
              "bodies[2].name: contains a control character");
  const std::string dh = R"({"schema_version": 1, "kind": "dynid.model", "name": "arm",
    "gravity": [0, 0, -9.81], "dh": {"convention": "modified", "inertia_about": "com", "joints": [
    {"name": "j1", "link": "l1", "type": "revolute", "a": 0, "d": 0.3, "alpha": 0,
     "inertial": {"m": 1, "com": [0, 0, 0], "inertia": {"Ixx": 0.01, "Ixy": 0, "Ixz": 0,
                  "Iyy": 0.01, "Iyz": 0, "Izz": 0.01}}},
    {"name": "j2", "link": "l1", "type": "revolute", "a": 0.1, "d": 0, "alpha": 0,
     "inertial": {"m": 1, "com": [0, 0, 0], "inertia": {"Ixx": 0.01, "Ixy": 0, "Ixz": 0,
                  "Iyy": 0.01, "Iyz": 0, "Izz": 0.01}}}]}})";
  try {
    modelFromJson(dh, "dh.json");
    ADD_FAILURE() << "two links named l1 were accepted";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("dh.joints[1].link: duplicate link name 'l1'"),
              std::string::npos)
        << e.what();
  }
  std::string renamed = dh;
  renamed.replace(renamed.find("\"link\": \"l1\"", 300), 12, "\"link\": \"l2\"");
  EXPECT_EQ(modelFromJson(renamed, "dh.json").numJoints(), 2);  // the same with distinct names
}

}  // namespace
}  // namespace dynid
