// dynid identify: OLS, WLS and pc estimates from simulated data.
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

TEST(Cli, IdentifyFromSimulatedData) {
  const std::string train = test::tempPath("train.csv"), test_csv = test::tempPath("test.csv"),
                    dir = test::tempPath("estimate");
  ASSERT_EQ(
      run("simulate --robot puma560 --drives --duration 4 --amplitude 1 --q0 0,0.8,1.5,0,0.8,0 "
          "--frequency 0.23,0.31,0.41,0.53,0.61,0.71 --bandwidth 8 --noise-tau 0.01 --seed 2 "
          "--out " +
          train)
          .code,
      0);
  ASSERT_EQ(
      run("simulate --robot puma560 --drives --duration 2 --controller fourier --amplitude 0.8 "
          "--q0 0,0.8,1.5,0,0.8,0 --seed 3 --out " +
          test_csv)
          .code,
      0);
  const Result r = run("identify --method wls --robot puma560 --drives --data " + train +
                       " --validate " + test_csv + " --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/estimate.json"));
  EXPECT_EQ(j["method"], "wls");
  EXPECT_EQ(j["num_base"], 58);
  const auto& p = j["base_parameters"][0];
  for (const char* key : {"name", "expression", "estimate", "std_dev", "relative_std_dev_percent"})
    EXPECT_TRUE(p.contains(key)) << key;
  ASSERT_EQ(j["validation"]["torque_rms"].size(), 6u);
  // 0.01 N m torque noise: the held-out prediction error stays of that order.
  for (const auto& rms : j["validation"]["torque_rms"]) EXPECT_LT(rms.get<double>(), 0.05);
  EXPECT_TRUE(contains(readFile(dir + "/estimate.md"), "| joint | residual RMS [N m] |"));
  // The same data with joint 1 exactly still: rank deficient, refused with the parameters named.
  Trajectory still_joint = readDatasetCsv(train);
  still_joint.q.row(0).setZero();
  still_joint.dq.row(0).setZero();
  still_joint.ddq.row(0).setZero();
  const std::string still = test::tempPath("still.csv");
  writeDatasetCsv(still, still_joint);
  const Result refused = run("identify --robot puma560 --drives --data " + still + " --out " + dir);
  EXPECT_EQ(refused.code, 1);
  EXPECT_TRUE(contains(refused.err, "do not excite")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "Iyy1R")) << refused.err;
  const Result bad_method =
      run("identify --method lasso --robot puma560 --data " + still + " --out " + dir);
  EXPECT_EQ(bad_method.code, 2);
  const Result wrong_robot =
      run("identify --robot puma560 --data " + test::tempPath("none.csv") + " --out " + dir);
  EXPECT_EQ(wrong_robot.code, 1);
}

}  // namespace
}  // namespace dynid
