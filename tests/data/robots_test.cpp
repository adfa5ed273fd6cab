#include "data/robots.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/urdf.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

TEST(Robots, LoadsEachKind) {
  EXPECT_EQ(loadRobot("puma560").numJoints(), 6);
  EXPECT_TRUE(loadRobot("puma560", {.drives = true}).drives_enabled);
  const Model tree = test::randomTree(2, {.drives = false});
  const std::string json = test::tempPath("tree.json"), urdf = test::tempPath("tree.urdf");
  writeFileAtomically(json, modelToJson(tree));
  writeFileAtomically(urdf, modelToUrdf(tree));
  EXPECT_EQ(loadRobot(json).standardParameters(), tree.standardParameters());
  EXPECT_TRUE(loadRobot(json, {.drives = true}).drives_enabled);
  EXPECT_EQ(loadRobot(urdf).numJoints(), tree.numJoints());
}

TEST(Robots, UnknownSpecIsAnInputError) {
  try {
    loadRobot("puma600");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown robot 'puma600'"), std::string::npos);
  }
}

}  // namespace
}  // namespace dynid
