#include "data/urdf_writeback.hpp"

#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/rnea.hpp"
#include "data/urdf.hpp"

namespace dynid {
namespace {

// Two moving links; link2 carries a fixed "tool" and the file has what a real URDF has: meshes,
// materials, a comment with a <link> inside, a transmission, a gazebo tag, an inertial with a
// rotated frame, a joint without <dynamics> and a self-closing link.
const char* kArm = R"(<?xml version="1.0"?>
<!-- <link name="link1"> inside a comment is not a link -->
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base"/>
  <link name="link1">
    <visual><geometry><mesh filename="package://arm/link1.dae"/></geometry><material name="grey"/></visual>
    <inertial>
      <origin xyz="0 0.02 0.1" rpy="0.3 0 0"/>
      <mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.015"/>
    </inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="link1"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="50" velocity="2"/>
    <dynamics damping="0.1" friction="0.05"/>
  </joint>
  <link name="link2">
    <inertial>
      <origin xyz="0.15 0 0" rpy="0 0 0"/>
      <mass value="1.5"/>
      <inertia ixx="0.005" ixy="0.001" ixz="0" iyy="0.02" iyz="0" izz="0.02"/>
    </inertial>
    <collision><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 0.2" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="30" velocity="2"/>
  </joint>
  <link name="tool">
    <inertial>
      <origin xyz="0 0 0.02" rpy="0 0 0"/>
      <mass value="0.3"/>
      <inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.0004" iyz="0" izz="0.0003"/>
    </inertial>
  </link>
  <joint name="tool_mount" type="fixed">
    <parent link="link2"/><child link="tool"/><origin xyz="0.3 0 0" rpy="0 1.5707963267948966 0"/>
  </joint>
  <transmission name="t1"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j1"><hardwareInterface>EffortJointInterface</hardwareInterface></joint>
  </transmission>
  <gazebo reference="link1"><mu1>0.2</mu1></gazebo>
</robot>
)";

/// The arm with new, consistent parameters: each body plus a small realisable body off its origin
/// (a sum of realisable bodies is realisable).
Model changedArm(const Model& arm) {
  Model out = arm;
  for (int i = 0; i < out.numJoints(); ++i) {
    Eigen::Matrix3d about_com = Eigen::Vector3d(0.002, 0.003, 0.004).asDiagonal();
    about_com(0, 1) = about_com(1, 0) = 0.0005;
    const Eigen::Vector3d com(0.05, -0.02 * (i + 1), 0.01);
    const Eigen::Matrix3d s = skew(com);
    RigidInertia<double> body = arm.inertias()[i];
    body.mass += 0.4;
    body.first_moment += 0.4 * com;
    body.inertia += about_com - 0.4 * s * s;
    out.setLinkInertia(i, body);
    DriveParameters<double> d = out.drives()[i];
    d[DriveTerm::kViscous] = 0.7 + i, d[DriveTerm::kCoulomb] = 0.3 + i,
    d[DriveTerm::kOffset] = -0.2;
    out.setDrive(i, d);
  }
  return out;
}

TEST(UrdfWriteBack, ReloadsToTheIdentifiedBodiesAndKeepsEverythingElse) {
  UrdfOptions options;
  options.drives = true;
  const Model arm = parseUrdf(kArm, "arm.urdf", options);
  ASSERT_EQ(arm.numJoints(), 2);
  const Model changed = changedArm(arm);
  const std::string written = urdfWithParameters(kArm, "arm.urdf", changed);
  const Model back = parseUrdf(written, "written.urdf", options);
  // The shortest round-trip decimals and the COM form's conversions: round-off of values ~1.
  EXPECT_LT((back.standardParameters() - changed.standardParameters()).cwiseAbs().maxCoeff(),
            1e-13);
  // The tool keeps its own <inertial>, the comment, meshes, transmission and gazebo tags stay.
  for (const char* kept :
       {"<!-- <link name=\"link1\"> inside a comment is not a link -->",
        "<mesh filename=\"package://arm/link1.dae\"/>", "<mass value=\"0.3\"/>",
        "<hardwareInterface>EffortJointInterface</hardwareInterface>", "<mu1>0.2</mu1>",
        "<limit lower=\"-2\" upper=\"2\" effort=\"30\" velocity=\"2\"/>",
        "<cylinder radius=\"0.04\" length=\"0.3\"/>"})
    EXPECT_NE(written.find(kept), std::string::npos) << kept << "\n" << written;
  EXPECT_EQ(written.find("<mass value=\"2\"/>"), std::string::npos);  // link1 replaced
  // <dynamics> carries Fv and Fc; j2 had none and gets one.
  EXPECT_NE(written.find("<dynamics damping=\"0.7\" friction=\"0.3\"/>"), std::string::npos);
  EXPECT_NE(written.find("<dynamics damping=\"1.7\" friction=\"1.3\"/>"), std::string::npos);
  EXPECT_DOUBLE_EQ(back.drives()[1][DriveTerm::kViscous], 1.7);
  // The torques of the reloaded file equal the identified model's (Fo has no URDF place: off).
  Model rigid_friction = changed;
  rigid_friction.setDriveTerms(back.driveTerms());
  Data a(rigid_friction), b(back);
  const Eigen::Vector2d q(0.3, -0.7), dq(0.5, -1.0), ddq(1.0, 2.0);
  const Eigen::VectorXd tau = rnea(rigid_friction, a, q, dq, ddq);
  EXPECT_LT((rnea(back, b, q, dq, ddq) - tau).norm(), 1e-12 * tau.norm());
  // Writing the file's own parameters back reloads to the same model.
  const Model same = parseUrdf(urdfWithParameters(kArm, "arm.urdf", arm), "same.urdf", options);
  EXPECT_LT((same.standardParameters() - arm.standardParameters()).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(UrdfWriteBack, RefusesWhatAUrdfCannotHold) {
  const Model arm = parseUrdf(kArm, "arm.urdf");
  // An inconsistent body.
  Model bad = arm;
  RigidInertia<double> body = bad.inertias()[0];
  body.inertia(2, 2) = -1.0;
  bad.setLinkInertia(0, body);
  try {
    urdfWithParameters(kArm, "arm.urdf", bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("link 'link1'"), std::string::npos) << e.what();
  }
  // A body lighter than the tool fixed to it.
  Model light = arm;
  RigidInertia<double> small;
  small.mass = 0.1;
  small.inertia = 0.001 * Eigen::Matrix3d::Identity();
  light.setLinkInertia(1, small);
  try {
    urdfWithParameters(kArm, "arm.urdf", light);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fixed to it"), std::string::npos) << e.what();
  }
  // A model that was not loaded from this file.
  Model other = arm;
  other.link_names[1] = "forearm";
  EXPECT_THROW(urdfWithParameters(kArm, "arm.urdf", other), ParseError);
}

}  // namespace
}  // namespace dynid
