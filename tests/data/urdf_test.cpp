#include "data/urdf.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/io.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

// A tree: base -> shoulder (revolute z) -> upper -> elbow (revolute y) -> fore -> tool (fixed),
// and upper -> side (prismatic x, a second branch).
const char* kTree = R"(<?xml version="1.0"?>
<robot name="tree">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0.1 0 0.2" rpy="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
  </link>
  <link name="fore">
    <inertial><origin xyz="0.15 0.01 0" rpy="0.1 0.2 0.3"/><mass value="1.0"/>
      <inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.012" iyz="0" izz="0.015"/></inertial>
  </link>
  <link name="tool">
    <inertial><origin xyz="0 0 0.05"/><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="side">
    <inertial><mass value="0.7"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.3" rpy="0 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="50" velocity="3"/>
    <dynamics damping="0.5" friction="0.2"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0.3 0 0.4" rpy="0.5 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="30" velocity="3"/>
  </joint>
  <joint name="tool_mount" type="fixed">
    <parent link="fore"/><child link="tool"/><origin xyz="0.3 0 0" rpy="0 1.5707963267948966 0"/>
  </joint>
  <joint name="slider" type="prismatic">
    <parent link="upper"/><child link="side"/><origin xyz="0 0.1 0"/>
    <axis xyz="1 1 0"/><limit lower="-0.2" upper="0.2" effort="10" velocity="1"/>
  </joint>
</robot>
)";

TEST(Urdf, LoadsATreeAndMergesFixedJoints) {
  const Model model = parseUrdf(kTree, "tree.urdf");
  ASSERT_EQ(model.numJoints(), 3);
  EXPECT_EQ(model.joint_names, (std::vector<std::string>{"shoulder", "elbow", "slider"}));
  EXPECT_EQ(model.parents(), (std::vector<int>{-1, 0, 0}));
  EXPECT_EQ(model.joint_types()[2], JointType::kPrismatic);
  EXPECT_NEAR(model.axes()[2].norm(), 1.0, 1e-15);
  // The tool is merged into "fore": 1.0 + 0.5 kg, its centre at 0.3 along x then 0.05 along the
  // rotated z (which is +x after the pi/2 pitch): first moment x = 1.0*0.15 + 0.5*0.35.
  EXPECT_DOUBLE_EQ(model.inertias()[1].mass, 1.5);
  EXPECT_NEAR(model.inertias()[1].first_moment.x(), 0.15 + 0.5 * 0.35, 1e-12);
  EXPECT_DOUBLE_EQ(model.limits[0].effort, 50.0);
  EXPECT_FALSE(model.driveTerms().any());
  const Model driven = parseUrdf(kTree, "tree.urdf", {.drives = true});
  EXPECT_EQ(driven.driveTerms(), DriveTerms::rotorAndFriction());
  EXPECT_DOUBLE_EQ(driven.drives()[0][DriveTerm::kViscous], 0.5);
  EXPECT_DOUBLE_EQ(driven.drives()[0][DriveTerm::kCoulomb], 0.2);
}

TEST(Urdf, FixedJointsByNameMergeLikeFixedOnes) {
  // The slider fixed by option gives the model of the file with it written fixed (at its zero
  // position: the joint origin): the same bodies, one joint fewer, 'side' merged into 'upper'.
  std::vector<std::string> warnings;
  const Model fixed = parseUrdf(kTree, "tree.urdf", {.fixed_joints = {"slider"}}, &warnings);
  std::string text = kTree;
  const std::size_t at = text.find(R"(<joint name="slider" type="prismatic">)");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 38, R"(<joint name="slider" type="fixed">)");
  const Model written = parseUrdf(text, "tree_fixed.urdf");
  ASSERT_EQ(fixed.numJoints(), 2);
  ASSERT_EQ(written.numJoints(), 2);
  EXPECT_EQ(fixed.joint_names, written.joint_names);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(fixed.inertias()[i].mass, written.inertias()[i].mass) << i;
    EXPECT_EQ(fixed.inertias()[i].first_moment, written.inertias()[i].first_moment) << i;
    EXPECT_EQ(fixed.inertias()[i].inertia, written.inertias()[i].inertia) << i;
  }
  EXPECT_DOUBLE_EQ(fixed.inertias()[0].mass, 2.0 + 0.7);  // 'upper' with 'side'
  // A name that is no joint of the file, or a fixed joint: refused, naming it.
  try {
    parseUrdf(kTree, "tree.urdf", {.fixed_joints = {"finger"}});
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'finger'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not in the file"), std::string::npos) << e.what();
  }
  try {
    parseUrdf(kTree, "tree.urdf", {.fixed_joints = {"tool_mount"}});
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("is fixed already"), std::string::npos) << e.what();
  }
  // A mimicking finger fixed by option: no mimic warning.
  std::string mimic = kTree;
  mimic.replace(mimic.find(R"(<axis xyz="1 1 0"/>)"), 19,
                R"(<axis xyz="1 1 0"/><mimic joint="elbow"/>)");
  warnings.clear();
  parseUrdf(mimic, "mimic.urdf", {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("dynid model export `fix_joints` slider"), std::string::npos)
      << warnings[0];
  warnings.clear();
  parseUrdf(mimic, "mimic.urdf", {.fixed_joints = {"slider"}}, &warnings);
  EXPECT_TRUE(warnings.empty());
}

TEST(Urdf, ExportLoadRoundTrip) {
  // A URDF model exports and reloads to the same parameters, placements and axes.
  const Model model = parseUrdf(kTree, "tree.urdf", {.drives = true});
  const Model back = parseUrdf(modelToUrdf(model), "exported.urdf", {.drives = true});
  ASSERT_EQ(back.numJoints(), model.numJoints());
  // Round-off of c = h/m, rpy <-> rotation and quaternion conversions.
  EXPECT_LT((back.standardParameters() - model.standardParameters()).cwiseAbs().maxCoeff(), 1e-12);
  for (int i = 0; i < model.numJoints(); ++i) {
    EXPECT_LT((back.joint_placements()[i].rotation - model.joint_placements()[i].rotation).norm(),
              1e-12);
    EXPECT_LT(
        (back.joint_placements()[i].translation - model.joint_placements()[i].translation).norm(),
        1e-12);
    EXPECT_LT((back.axes()[i] - model.axes()[i]).norm(), 1e-12);
    EXPECT_EQ(back.limits[i].lower, model.limits[i].lower);
  }
}

TEST(Urdf, DenavitHartenbergModelsExportWithIdenticalDynamics) {
  // The PUMA's link frames follow its joints, which URDF cannot express: the export uses joint
  // frames, so parameters differ but every torque is the same.
  for (const Model& model : {makePuma560(), test::randomTree(3, {.prismatic = false})}) {
    const Model back = parseUrdf(modelToUrdf(model), "exported.urdf");
    Data a(model), b(back);
    std::mt19937_64 rng(1);
    for (int trial = 0; trial < 5; ++trial) {
      const int n = model.numJoints();
      const Eigen::VectorXd q = test::randomVector(rng, n, 2), dq = test::randomVector(rng, n, 2),
                            ddq = test::randomVector(rng, n, 2);
      Model gravity_fixed = back;
      gravity_fixed.setGravity(model.gravity());  // URDF has no gravity element
      gravity_fixed.finalize();
      Data c(gravity_fixed);
      const Eigen::VectorXd expected = rnea(model, a, q, dq, ddq);
      EXPECT_LT((rnea(gravity_fixed, c, q, dq, ddq) - expected).norm(),
                1e-12 * (1 + expected.norm()));
    }
  }
}

/// Replaces `from` by `to` in the tree document.
std::string edited(const std::string& from, const std::string& to) {
  std::string text = kTree;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

void expectError(const std::string& text, const std::vector<std::string>& fragments) {
  try {
    parseUrdf(text, "robot.urdf");
    FAIL() << "expected ParseError for " << fragments[0];
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "robot.urdf");
    for (const std::string& f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "'" << f << "' not in: " << e.what();
  }
}

TEST(Urdf, RejectsBadInputWithFileAndElement) {
  expectError(edited(R"(type="prismatic")", R"(type="floating")"),
              {"robot.urdf:", "joint 'slider'", "a floating-base robot is loaded as one"});
  expectError(edited(R"(type="prismatic")", R"(type="planar")"),
              {"joint 'slider'", "planar joints are not supported"});
  expectError(edited(R"(<mass value="0.7"/>)", R"(<mass value="-0.7"/>)"),
              {"robot.urdf:16", "link 'side'", "negative mass"});
  expectError(edited(R"(<mass value="0.7"/>)", ""), {"link 'side'", "mass"});
  expectError(edited(R"(<mass value="0.7"/>)", R"(<mass value="nan"/>)"), {"robot.urdf"});
  expectError(edited(R"(ixx="0.002")", R"(ixx="1e999")"), {"robot.urdf"});
  expectError(edited(R"(<parent link="upper"/><child link="side"/>)",
                     R"(<parent link="nowhere"/><child link="side"/>)"),
              {"robot.urdf", "nowhere"});
  // A second root: "side" loses its parent joint.
  std::string two_roots = kTree;
  const std::size_t start = two_roots.find("  <joint name=\"slider\"");
  two_roots.erase(start, two_roots.find("</joint>", start) + 9 - start);
  expectError(two_roots, {"robot.urdf", "root"});
  // A cycle: base becomes the child of fore.
  expectError(
      edited(
          "</robot>",
          R"(<joint name="loop" type="fixed"><parent link="fore"/><child link="base"/></joint></robot>)"),
      {"robot.urdf", "root"});
  expectError(edited(R"(<axis xyz="0 1 0"/>)", R"(<axis xyz="0 0 0"/>)"),
              {"robot.urdf:25", "joint 'elbow'", "zero vector"});
  expectError("<robot", {"robot.urdf", "urdfdom"});
  // A document that is not UTF-8 is refused with its line (found by fuzzing: a Latin-1 robot
  // name loaded and its exported URDF did not load back; broken UTF-8 made TinyXML read past
  // the end of the document); names with control characters go nowhere either (they go into
  // JSON, XML and HTML outputs).
  expectError(edited("<?xml version=\"1.0\"?>\n<robot name=\"tree\">",
                     "<robot name=\"tr\xe9"
                     "e\">"),
              {"robot.urdf:1", "byte 0xe9", "UTF-8"});
  std::string control = kTree;
  for (std::size_t k = control.find("\"fore\""); k != std::string::npos;
       k = control.find("\"fore\"", k))
    control.replace(k, 6, "\"fo\x01re\"");
  expectError(control, {"robot.urdf", "link 'fo\\x01re'", "UTF-8"});
  expectError(edited(R"(joint name="elbow")", "joint name=\"elb\xffow\""),
              {"robot.urdf:", "byte 0xff", "UTF-8"});
}

TEST(Urdf, WarnsOrFailsOnAMovingLinkWithoutInertial) {
  const std::string text = edited(R"(<inertial><mass value="0.7"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial>)",
                                  "");
  std::vector<std::string> warnings;
  const Model model = parseUrdf(text, "robot.urdf", {}, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("link 'side' has no <inertial>"), std::string::npos);
  EXPECT_EQ(model.inertias()[2].mass, 0.0);
  EXPECT_THROW(parseUrdf(text, "robot.urdf", {.strict = true}), ParseError);
}

TEST(Urdf, MissingFileNamesThePath) {
  try {
    loadUrdf("/nonexistent/robot.urdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf"), std::string::npos);
  }
}

// What a URDF export leaves out (`model export --format urdf` prints it as notes): the drive terms
// with no <dynamics> attribute, and a gravity other than URDF readers assume.
TEST(UrdfExport, SaysWhatItCannotCarry) {
  Model puma = makePuma560(true);  // ia, fv, fc, fa
  std::vector<std::string> notes = urdfCannotCarry(puma);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("rotor inertia (Ia)"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("Coulomb asymmetry (Fa)"), std::string::npos) << notes[1];
  EXPECT_TRUE(urdfCannotCarry(makePuma560(false)).empty());
  puma.setGravity(Eigen::Vector3d(0.0, 0.0, -1.62));  // the Moon
  notes = urdfCannotCarry(puma);
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_NE(notes[2].find("(0, 0, -1.62) m/s^2"), std::string::npos) << notes[2];
}

}  // namespace
}  // namespace dynid
