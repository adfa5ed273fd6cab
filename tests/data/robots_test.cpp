#include "data/robots.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "data/urdf.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

RobotOptions withDrives() {
  RobotOptions out;
  out.drives = true;
  return out;
}

RobotOptions withTerms(const char* terms) {
  RobotOptions out;
  out.drive_terms = parseDriveTerms(terms);
  return out;
}

TEST(Robots, LoadsEachKind) {
  EXPECT_EQ(loadRobot("puma560").numJoints(), 6);
  const Model tree = test::randomTree(2, {.drives = false});
  const std::string json = test::tempPath("tree.json"), urdf = test::tempPath("tree.urdf");
  writeFileAtomically(json, modelToJson(tree));
  writeFileAtomically(urdf, modelToUrdf(tree));
  EXPECT_EQ(loadRobot(json).standardParameters(), tree.standardParameters());
  EXPECT_EQ(loadRobot(urdf).numJoints(), tree.numJoints());
}

TEST(Robots, DrivesGiveEachRobotItsOwnTermsAndDriveTermsOverride) {
  // --drives: the robot's published drive model, or ia,fv,fc for a file that names none.
  EXPECT_FALSE(loadRobot("puma560").driveTerms().any());
  EXPECT_EQ(loadRobot("puma560", withDrives()).driveTerms(), kPuma560DriveTerms);
  EXPECT_EQ(loadRobot("panda", withDrives()).driveTerms(), kPandaDriveTerms);
  const Model tree = test::randomTree(2, {.drives = false});
  const std::string json = test::tempPath("terms.json"), urdf = test::tempPath("terms.urdf");
  writeFileAtomically(json, modelToJson(tree));
  writeFileAtomically(urdf, modelToUrdf(tree));
  EXPECT_EQ(loadRobot(json, withDrives()).driveTerms(), DriveTerms::rotorAndFriction());
  EXPECT_EQ(loadRobot(urdf, withDrives()).driveTerms(), DriveTerms::rotorAndFriction());
  // --drive-terms: exactly those, the values kept where the robot has them.
  const Model puma = loadRobot("puma560", withTerms("fv,fo"));
  EXPECT_EQ(driveTermsText(puma.driveTerms()), "fv,fo");
  EXPECT_EQ(puma.parameterLayout().size(), 6 * 12);
  EXPECT_EQ(puma.drives()[0][DriveTerm::kViscous],
            makePuma560(true).drives()[0][DriveTerm::kViscous]);
  EXPECT_EQ(driveTermsText(loadRobot(urdf, withTerms("fc")).driveTerms()), "fc");
  EXPECT_FALSE(loadRobot("panda", withTerms("none")).driveTerms().any());
  // A JSON model keeps its own terms unless told otherwise.
  Model sensor = tree;
  sensor.setDriveTerms(kPandaDriveTerms);
  writeFileAtomically(json, modelToJson(sensor));
  EXPECT_EQ(loadRobot(json).driveTerms(), kPandaDriveTerms);
  EXPECT_EQ(loadRobot(json, withDrives()).driveTerms(), kPandaDriveTerms);
  EXPECT_EQ(driveTermsText(loadRobot(json, withTerms("ia")).driveTerms()), "ia");
}

TEST(Robots, AUrdfsDynamicsAreReadBackAsViscousAndCoulombFriction) {
  // The PUMA exported with its drives: <dynamics damping= friction=> per joint, as dynid's own
  // write-back fills them.
  const Model puma = makePuma560(true);
  const std::string urdf = test::writeTemp("dynamics.urdf", modelToUrdf(puma));
  std::vector<std::string> warnings;
  const Model read = loadRobot(urdf, {}, &warnings);
  EXPECT_EQ(read.driveTerms().mask,
            DriveTerms::of({DriveTerm::kViscous, DriveTerm::kCoulomb}).mask);
  for (int j = 0; j < 6; ++j) {
    EXPECT_EQ(read.drives()[j][DriveTerm::kViscous], puma.drives()[j][DriveTerm::kViscous]);
    EXPECT_EQ(read.drives()[j][DriveTerm::kCoulomb], puma.drives()[j][DriveTerm::kCoulomb]);
  }
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("read as viscous and Coulomb friction (drive terms fv,fc"),
            std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[0].find("`drive_terms` none gives the rigid model"), std::string::npos);
  // Asked for none: rigid, and nothing said.
  warnings.clear();
  EXPECT_FALSE(loadRobot(urdf, withTerms("none"), &warnings).driveTerms().any());
  EXPECT_TRUE(warnings.empty());
  // Without <dynamics> (a rigid export): rigid, and nothing said.
  const std::string rigid = test::writeTemp("rigid.urdf", modelToUrdf(makePuma560(false)));
  EXPECT_FALSE(loadRobot(rigid, {}, &warnings).driveTerms().any());
  EXPECT_TRUE(warnings.empty());
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
