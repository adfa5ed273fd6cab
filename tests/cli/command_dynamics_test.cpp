// dynid dynamics: RNEA, CRBA and ABA at one state, as JSON.
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

TEST(Cli, DynamicsJson) {
  const Result r =
      run("dynamics --robot puma560 --q 0,0.7853981633974483,3.141592653589793,0,"
          "0.7853981633974483,0 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["schema_version"], 1);
  ASSERT_EQ(j["tau"].size(), 6u);
  ASSERT_EQ(j["M"].size(), 6u);
  ASSERT_EQ(j["ddq"].size(), 6u);
  // Robotics Toolbox p560.gravload(qn) = (0, 31.6399, 6.0351, 0, 0.0283, 0).
  EXPECT_NEAR(j["tau"][1].get<double>(), 31.6399, 1e-4);
  EXPECT_NEAR(j["tau"][2].get<double>(), 6.0351, 1e-4);
  const Result with_tau =
      run("dynamics --robot puma560 --drives --q 0,0,0,0,0,0 --dq=-1,0,0,0,0,0 "
          "--tau 1,2,3,4,5,6 --json");
  ASSERT_EQ(with_tau.code, 0) << with_tau.err;
  EXPECT_EQ(nlohmann::json::parse(with_tau.out)["tau"][5], 6.0);
  EXPECT_EQ(run("dynamics --robot puma560 --q -0.5,0,0,0,0,0").code, 0);
}

}  // namespace
}  // namespace dynid
