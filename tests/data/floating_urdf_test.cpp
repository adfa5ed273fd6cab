// Floating-base robots from URDF (data/urdf.hpp's loadFloatingUrdf): the base body keeps the
// root's inertia and every link fixed to it, every link is a named frame, and the two example
// robots (examples/floating/) load whole.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/urdf.hpp"

namespace dynid {
namespace {

// world -(floating)-> trunk (2 kg) -(fixed)-> battery (1 kg at x 0.1) ; trunk -(revolute)-> leg.
const char* kHopper = R"(<?xml version="1.0"?>
<robot name="hopper">
  <link name="world"/>
  <link name="trunk">
    <inertial><origin xyz="0 0 0.05"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
  </link>
  <link name="battery">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="leg">
    <inertial><origin xyz="0 0 -0.2"/><mass value="0.5"/>
      <inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="foot"/>
  <joint name="float" type="floating"><parent link="world"/><child link="trunk"/></joint>
  <joint name="mount" type="fixed">
    <parent link="trunk"/><child link="battery"/><origin xyz="0.1 0 0"/>
  </joint>
  <joint name="hip" type="revolute">
    <parent link="trunk"/><child link="leg"/><origin xyz="0 0 -0.1"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="50" velocity="3"/>
  </joint>
  <joint name="sole" type="fixed">
    <parent link="leg"/><child link="foot"/><origin xyz="0 0 -0.4"/>
  </joint>
</robot>
)";

TEST(FloatingUrdf, TheBaseKeepsTheRootAndWhatIsFixedToIt) {
  const FloatingModel model = parseFloatingUrdf(kHopper, "hopper.urdf");
  EXPECT_EQ(model.baseName(), "trunk");
  EXPECT_EQ(model.numJoints(), 1);
  EXPECT_DOUBLE_EQ(model.baseInertia().mass, 3.0);
  EXPECT_NEAR(model.baseInertia().first_moment.x(), 0.1, 1e-15);  // the battery's 1 kg at 0.1 m
  EXPECT_NEAR(model.baseInertia().first_moment.z(), 0.1, 1e-15);  // the trunk's 2 kg at 0.05 m
  const BodyFrame* foot = model.findFrame("foot");
  ASSERT_NE(foot, nullptr);
  EXPECT_EQ(foot->body, 0);
  EXPECT_NEAR(foot->placement.translation.z(), -0.4, 1e-15);
  ASSERT_NE(model.findFrame("battery"), nullptr);
  EXPECT_EQ(model.findFrame("battery")->body, -1);
  EXPECT_EQ(model.findFrame("trunk")->body, -1);
  EXPECT_EQ(model.findFrame("leg")->body, 0);
}

TEST(FloatingUrdf, AWorldWithMassIsSaidToBeTheWorld) {
  std::string massive = kHopper;
  massive.replace(
      massive.find(R"(<link name="world"/>)"), 20,
      R"(<link name="world"><inertial><mass value="100"/>)"
      R"(<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>)");
  std::vector<std::string> warnings;
  const FloatingModel model = parseFloatingUrdf(massive, "hopper.urdf", {}, &warnings);
  EXPECT_DOUBLE_EQ(model.baseInertia().mass, 3.0);  // the world's 100 kg are not the robot's
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("link 'world'"), std::string::npos) << warnings[0];
}

TEST(FloatingUrdf, AFloatingJointIsTheFloatingLoadersOnly) {
  try {
    parseUrdf(kHopper, "hopper.urdf");
    FAIL() << "a fixed-base load took a floating joint";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("`floating_base`"), std::string::npos) << e.what();
  }
  // Below the root, a floating joint is refused by the floating loader too.
  std::string nested = kHopper;
  nested.replace(nested.find(R"(<joint name="hip" type="revolute">)"), 35,
                 R"(<joint name="hip" type="floating">)");
  EXPECT_THROW(parseFloatingUrdf(nested, "nested.urdf"), ParseError);
}

/// The sum of every <mass value> in a URDF's text.
double massInText(const std::string& text) {
  const std::regex mass(R"(<mass value="([-0-9.eE+]+)\")");
  double total = 0.0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), mass); it != std::sregex_iterator();
       ++it)
    total += std::stod((*it)[1]);
  return total;
}

struct ExampleRobot {
  const char* path;
  int joints;
  std::vector<std::string> contacts;
};

class ExampleRobots : public ::testing::TestWithParam<ExampleRobot> {};

TEST_P(ExampleRobots, LoadWholeWithTheirContactFrames) {
  const std::string path = std::string(DYNID_SOURCE_DIR) + "/" + GetParam().path;
  const FloatingModel model = loadFloatingUrdf(path);
  EXPECT_EQ(model.numJoints(), GetParam().joints);
  double mass = model.baseInertia().mass;
  for (const RigidInertia<double>& I : model.limbs().inertias()) mass += I.mass;
  // Every link's mass is in the model: the base keeps what a fixed base would drop.
  EXPECT_NEAR(mass, massInText(readFile(path)), 1e-9 * mass);
  for (const std::string& name : GetParam().contacts) {
    const BodyFrame* frame = model.findFrame(name);
    ASSERT_NE(frame, nullptr) << name;
    EXPECT_GE(frame->body, 0) << name;  // on a limb
  }
}

INSTANTIATE_TEST_SUITE_P(
    Robots, ExampleRobots,
    ::testing::Values(ExampleRobot{"examples/floating/anymal_c/anymal.urdf",
                                   12,
                                   {"LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT"}},
                      ExampleRobot{
                          "examples/floating/romeo/romeo_small.urdf", 31, {"l_sole", "r_sole"}}));

}  // namespace
}  // namespace dynid
