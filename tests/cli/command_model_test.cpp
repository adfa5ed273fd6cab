// dynid model: export to JSON and URDF and load again with the same dynamics.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, ModelExportAndReload) {
  const std::string json = test::tempPath("puma.json"), urdf = test::tempPath("puma.urdf");
  ASSERT_EQ(run("model export --robot puma560 --drives --format json --out " + json).code, 0);
  const Result rigid = run("model export --robot puma560 --format urdf --out " + urdf);
  ASSERT_EQ(rigid.code, 0) << rigid.err;
  EXPECT_FALSE(contains(rigid.err, "note:")) << rigid.err;  // a rigid PUMA: URDF carries it all
  // With its drives: rotor inertia and the Coulomb asymmetry have no URDF element, said.
  const Result driven = run("model export --robot puma560 --drives --format urdf --out " +
                            test::tempPath("puma_drives.urdf"));
  ASSERT_EQ(driven.code, 0) << driven.err;
  EXPECT_TRUE(contains(driven.err, "note: URDF has no element for rotor inertia (Ia)"))
      << driven.err;
  const std::string args = " --q 0.1,0.2,0.3,0.4,0.5,0.6 --dq 1,1,1,1,1,1 --json";
  const auto builtin = nlohmann::json::parse(run("dynamics --robot puma560 --drives" + args).out);
  const auto reloaded = nlohmann::json::parse(run("dynamics --robot " + json + args).out);
  EXPECT_EQ(builtin["tau"], reloaded["tau"]);
  EXPECT_EQ(run("dynamics --robot " + urdf + args).code, 0);
  const Result check = run("model check --robot puma560 --json");
  EXPECT_EQ(check.code, 1);  // the published link 1 and link 3 violate the triangle inequality
  const auto report = nlohmann::json::parse(check.out);
  EXPECT_FALSE(report["consistent"].get<bool>());
  EXPECT_EQ(report["violations"].size(), 2u);
  const Result show = run("model show --robot puma560 --drives");
  EXPECT_EQ(show.code, 0);
  EXPECT_TRUE(contains(show.out, "Ia6")) << show.out;
  EXPECT_TRUE(contains(show.out, "Fa6")) << show.out;  // the PUMA's asymmetric Coulomb term
}

TEST(Cli, DriveTermsPickTheColumnsAndBadTermsAreUsageErrors) {
  const Result panda = run("model show --robot panda --drives");
  ASSERT_EQ(panda.code, 0) << panda.err;
  EXPECT_TRUE(contains(panda.out, "drive terms fv,fc,fo")) << panda.out;
  EXPECT_TRUE(contains(panda.out, "Fo7")) << panda.out;
  EXPECT_FALSE(contains(panda.out, "Ia1")) << panda.out;
  const Result picked = run("model show --robot puma560 --drive-terms ia,fo");
  ASSERT_EQ(picked.code, 0) << picked.err;
  EXPECT_TRUE(contains(picked.out, "Fo6") && contains(picked.out, "Ia6")) << picked.out;
  EXPECT_FALSE(contains(picked.out, "Fv6")) << picked.out;
  const Result bad = run("model show --robot panda --drive-terms fv,friction");
  EXPECT_EQ(bad.code, 2);
  EXPECT_TRUE(contains(bad.err, "unknown drive term 'friction'")) << bad.err;
  EXPECT_EQ(run("model show --robot panda --drives --drive-terms fv").code, 2);
}

TEST(Cli, ModelExportFixesAGrippersFingers) {
  // A URDF arm with two prismatic fingers, one mimicking the other: exported with the fingers
  // fixed, it reloads as the arm alone (their mass merged), without the mimic warning.
  const std::string gripper = test::tempPath("gripper.urdf"), arm = test::tempPath("arm.urdf");
  writeFileAtomically(gripper, R"(<?xml version="1.0"?>
<robot name="g">
  <link name="base"/>
  <link name="l1"><inertial><mass value="2"/><origin xyz="0 0 0.1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="f1"><inertial><mass value="0.1"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>
  <link name="f2"><inertial><mass value="0.1"/>
    <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="finger1" type="prismatic"><parent link="l1"/><child link="f1"/>
    <origin xyz="0 0.02 0.2"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="10" velocity="0.1"/></joint>
  <joint name="finger2" type="prismatic"><parent link="l1"/><child link="f2"/>
    <origin xyz="0 -0.02 0.2"/><axis xyz="0 -1 0"/>
    <limit lower="0" upper="0.04" effort="10" velocity="0.1"/><mimic joint="finger1"/></joint>
</robot>
)");
  const Result whole = run("model show --robot " + gripper);
  EXPECT_TRUE(contains(whole.out, "3 joints")) << whole.out;
  EXPECT_TRUE(contains(whole.err, "dynid model export --fix-joints finger2")) << whole.err;
  const Result out = run("model export --robot " + gripper +
                         " --fix-joints finger1,finger2 --format urdf --out " + arm);
  ASSERT_EQ(out.code, 0) << out.err;
  EXPECT_FALSE(contains(out.err, "mimic")) << out.err;
  const Result shown = run("model show --robot " + arm);
  EXPECT_TRUE(contains(shown.out, "1 joints")) << shown.out;
  EXPECT_TRUE(contains(shown.out, "  m1 ") && contains(shown.out, " 2.2  mx1")) << shown.out;
  EXPECT_EQ(run("model show --robot puma560 --fix-joints j1").code, 2);
  const Result unknown = run("model show --robot " + gripper + " --fix-joints thumb");
  EXPECT_EQ(unknown.code, 1);
  EXPECT_TRUE(contains(unknown.err, "joint 'thumb': is not in the file")) << unknown.err;
}

}  // namespace
}  // namespace dynid
