// dynid predict: a saved estimate applied to data.
#include <filesystem>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "data/io.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

TEST(Cli, PredictReproducesTheEstimatesResidualsAndRefusesAnotherRobot) {
  const std::string train = test::tempPath("predict_train.csv"),
                    est = test::tempPath("predict_estimate"), out = test::tempPath("predicted");
  ASSERT_EQ(run("simulate --robot puma560 --drives --duration 3 --amplitude 1 --q0 "
                "0,0.8,1.5,0,0.8,0 --frequency 0.23,0.31,0.41,0.53,0.61,0.71 --bandwidth 8 "
                "--noise-tau 0.05 --seed 4 --out " +
                train)
                .code,
            0);
  ASSERT_EQ(
      run("identify --method wls --robot puma560 --drives --data " + train + " --out " + est).code,
      0);
  const Result r =
      run("predict --estimate " + est + "/estimate.json --data " + train + " --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto e = nlohmann::json::parse(readFile(est + "/estimate.json"));
  const auto p = nlohmann::json::parse(readFile(out + "/prediction.json"));
  EXPECT_EQ(p["robot_spec"], "puma560");
  // The estimate on its own training data: its residuals again, to round-off (RNEA against the
  // regressor times the base parameters, on torques of order 10 N m).
  ASSERT_EQ(p["residual_rms"].size(), 6u);
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(p["residual_rms"][j].get<double>(), e["residual_rms"][j].get<double>(),
                1e-9 * e["residual_rms"][j].get<double>())
        << "joint " << j + 1;
  EXPECT_NEAR(p["relative_error"].get<double>(), e["relative_error"].get<double>(), 1e-9);
  const std::string csv = readFile(out + "/predicted.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "t,tau1,tau2,tau3,tau4,tau5,tau6,tau_hat1,tau_hat2,"
            "tau_hat3,tau_hat4,tau_hat5,tau_hat6,band1,band2,band3,band4,band5,band6");
  // Another robot (a URDF of 6 joints without drives): named, nothing written.
  const std::string urdf = test::tempPath("predict_other.urdf"), never = test::tempPath("never");
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
  const Result other = run("predict --estimate " + est + "/estimate.json --robot " + urdf +
                           " --data " + train + " --out " + never);
  EXPECT_EQ(other.code, 1);
  EXPECT_TRUE(contains(other.err, "is not the robot the estimate was made for")) << other.err;
  // Not an estimate.
  const Result junk = run("predict --estimate " + train + " --data " + train + " --out " + never);
  EXPECT_EQ(junk.code, 1);
  EXPECT_TRUE(contains(junk.err, train)) << junk.err;
  EXPECT_FALSE(std::filesystem::exists(never));
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

using test::contains;
using test::Result;
using test::run;

// Through prepare (its 10 Hz low-pass, recorded in prepare.json), predict reproduces the filter
// on the friction as identify's held-out error does, and gives that error again.
TEST(Cli, PredictOnAPreparedLogGivesIdentifysHeldOutError) {
  const std::string dir = test::tempPath("predict_prepared");
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("simulate --robot puma560 --drives --controller fourier --duration 12 "
                "--noise-q 1e-5 --noise-tau 0.5 --seed 7 --out " +
                dir + "/sim.csv")
                .code,
            0);
  ASSERT_EQ(run("prepare --log " + dir +
                "/sim.csv --q 'q*' --tau 'tau*' --validate-fraction "
                "0.25 --out " +
                dir + "/prep")
                .code,
            0);
  ASSERT_EQ(run("identify --method ols --robot puma560 --drives --data " + dir +
                "/prep/train.csv --validate " + dir + "/prep/validate.csv --out " + dir + "/est")
                .code,
            0);
  // The estimate's rest velocities are its training data's; predict is given them.
  const auto e = nlohmann::json::parse(readFile(dir + "/est/estimate.json"));
  std::string rest;
  for (const auto& v : e["rest_velocity"]["velocity"]) rest += (rest.empty() ? "" : ",") + v.dump();
  const Result r = run("predict --estimate " + dir + "/est/estimate.json --data " + dir +
                       "/prep/validate.csv --rest-velocity " + rest + " --out " + dir + "/pred");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "compared with the filtered torque")) << r.out;
  EXPECT_TRUE(contains(r.out, "(prepare.json: the torque's low-pass)")) << r.out;
  const auto p = nlohmann::json::parse(readFile(dir + "/pred/prediction.json"));
  EXPECT_EQ(p["schema_version"], 6);
  EXPECT_EQ(p["provenance"]["command"][1], "predict");
  // The robot predicted with, embedded (with the estimate's parameters), and where it came from.
  EXPECT_EQ(p["model"]["name"], e["model"]["name"]);
  EXPECT_EQ(p["model_source"], e["model_source"]);
  EXPECT_EQ(p["torque_filter"]["cutoff_hz"], 10.0);
  // The same sums in another order (1e-12), the shortest decimal of each kept in the files.
  EXPECT_NEAR(p["relative_error"].get<double>(), e["validation"]["relative_error"].get<double>(),
              1e-12 * e["validation"]["relative_error"].get<double>());
  const Result none = run("predict --estimate " + dir + "/est/estimate.json --data " + dir +
                          "/prep/validate.csv --torque-filter none --out " + dir + "/plain");
  ASSERT_EQ(none.code, 0) << none.err;
  EXPECT_EQ(nlohmann::json::parse(readFile(dir + "/plain/prediction.json"))["torque_filter"],
            nullptr);
}

TEST(Cli, PredictDrawsTheBandAndWarnsWhenItDoesNotCoverTheData) {
  const std::string dir = test::tempPath("cli_predict_band");
  std::filesystem::create_directories(dir);
  for (const std::string& args :
       {"--noise-tau 0.1 --seed 3 --out " + dir + "/train.csv",
        "--noise-tau 0.1 --seed 4 --phase 0.5 --out " + dir + "/same.csv",
        "--noise-tau 0.4 --seed 5 --phase 0.5 --out " + dir + "/noisy.csv"})
    ASSERT_EQ(run("simulate --robot puma560 --duration 10 " + args).code, 0) << args;
  ASSERT_EQ(run("identify --robot puma560 --data " + dir + "/train.csv --out " + dir + "/est").code,
            0);
  const std::string estimate = dir + "/est/estimate.json";
  const auto e = nlohmann::json::parse(readFile(estimate));
  ASSERT_TRUE(e.contains("base_covariance"));
  EXPECT_EQ(e["base_covariance"]["columns"].size(), e["num_base"].get<std::size_t>());

  const Result same = run("predict --estimate " + estimate + " --data " + dir + "/same.csv --out " +
                          dir + "/p_same");
  ASSERT_EQ(same.code, 0) << same.err;
  EXPECT_TRUE(contains(same.out, "95 % band coverage per joint")) << same.out;
  EXPECT_FALSE(contains(same.out, "warning")) << same.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/p_same/prediction.json"));
  for (const auto& c : j["band"]["coverage"]) {
    // 10001 samples with the training noise: 95 % within the binomial spread and the estimate's.
    EXPECT_GT(c.get<double>(), 0.93);
    EXPECT_LT(c.get<double>(), 0.97);
  }
  EXPECT_TRUE(contains(readFile(dir + "/p_same/predicted.csv").substr(0, 300), ",band6\n"));

  const Result noisy = run("predict --estimate " + estimate + " --data " + dir +
                           "/noisy.csv --out " + dir + "/p_noisy");
  ASSERT_EQ(noisy.code, 0) << noisy.err;
  EXPECT_TRUE(contains(noisy.out, "warning: joint 1: the 95 % band covers")) << noisy.out;
  const auto k = nlohmann::json::parse(readFile(dir + "/p_noisy/prediction.json"));
  EXPECT_EQ(k["band"]["outside_expected"].size(), 6u);

  // An estimate made before the covariance was recorded: the prediction without a band.
  nlohmann::json old = e;
  old.erase("base_covariance");
  writeFileAtomically(dir + "/old.json", old.dump());
  const Result plain = run("predict --estimate " + dir + "/old.json --data " + dir +
                           "/same.csv --out " + dir + "/p_old");
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_TRUE(contains(plain.out, "no band")) << plain.out;
  EXPECT_FALSE(contains(readFile(dir + "/p_old/predicted.csv").substr(0, 300), "band1"));
}

// An arm holding its pose throughout (simulate --stiction): every joint at rest, no row compared;
// predict says so (coverage and RMS n/a) instead of a 0 % coverage and its warning.
TEST(Cli, PredictOnAnArmAtRestThroughoutComparesNoRowAndSaysSo) {
  const std::string dir = test::tempPath("cli_predict_rest");
  std::filesystem::create_directories(dir);
  const std::string common = "simulate --robot puma560 --drives --stiction --noise-tau 0.3 ";
  ASSERT_EQ(run(common + "--controller fourier --duration 10 --noise-dq 0.001 --seed 11 --out " +
                dir + "/train.csv")
                .code,
            0);
  ASSERT_EQ(run(common + "--amplitude 0 --duration 2 --noise-dq 0.001 --seed 12 --out " + dir +
                "/hold.csv")
                .code,
            0);
  ASSERT_EQ(
      run("identify --robot puma560 --drives --data " + dir + "/train.csv --out " + dir + "/est")
          .code,
      0);
  const Result r = run("predict --estimate " + dir + "/est/estimate.json --data " + dir +
                       "/hold.csv --out " + dir + "/p");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "per joint RMS [N m]: n/a n/a n/a n/a n/a n/a")) << r.out;
  EXPECT_TRUE(contains(r.out, "95 % band coverage per joint [%]: n/a n/a n/a n/a n/a n/a"))
      << r.out;
  EXPECT_FALSE(contains(r.out, "warning")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/p/prediction.json"));
  for (const auto& c : j["band"]["coverage"]) EXPECT_TRUE(c.is_null()) << j["band"];
  EXPECT_TRUE(j["band"]["outside_expected"].empty());
  // At rest the residual's spread is the sensor's noise, as the measured torque's: within 2 %,
  // the prediction's own spread there (velocity noise through Fv) being under 0.01 of 0.3 N m.
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(j["at_rest"]["residual_std"][k].get<double>(),
                j["at_rest"]["measured_std"][k].get<double>(),
                0.02 * j["at_rest"]["measured_std"][k].get<double>())
        << k;
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

TEST(Cli, PredictWithARobotModelItselfAndWithTheUrdfIdentifyWrote) {
  // --robot alone predicts with the model's own parameters: on its own noise-free simulation the
  // torques come back to round-off (the dataset holds the simulated ddq and tau).
  const std::string dir = test::tempPath("predict_model");
  std::filesystem::remove_all(dir);
  const std::string train = dir + "/train.csv";
  std::filesystem::create_directories(dir);
  const std::string urdf = std::string(DYNID_SOURCE_DIR) + "/tests/fuzz/corpus/urdf/puma560.urdf";
  ASSERT_EQ(run("simulate --robot " + urdf + " --duration 2 --seed 3 --out " + train).code, 0);
  const test::Result own =
      run("predict --robot " + urdf + " --data " + train + " --out " + dir + "/own");
  ASSERT_EQ(own.code, 0) << own.err;
  EXPECT_TRUE(test::contains(own.out, "no band: a model has no covariance")) << own.out;
  const auto p = nlohmann::json::parse(readFile(dir + "/own/prediction.json"));
  EXPECT_EQ(p["method"], "model");
  EXPECT_TRUE(p["estimate"].is_null());
  // 1e-9 relative: RNEA on the model against the simulator's ABA-consistent torques, both in
  // double precision on torques of order 10 N m.
  EXPECT_LT(p["relative_error"].get<double>(), 1e-9);
  // The loop a user closes: identify (pc) -> --write-urdf -> predict --robot on the written URDF
  // gives identify's own fit on its training data (the URDF carries every identified parameter
  // the data can see).
  ASSERT_EQ(run("identify --method pc --robot " + urdf + " --data " + train + " --out " + dir +
                "/est --write-urdf " + dir + "/identified.urdf")
                .code,
            0);
  const test::Result written = run("predict --robot " + dir + "/identified.urdf --data " + train +
                                   " --out " + dir + "/written");
  ASSERT_EQ(written.code, 0) << written.err;
  const test::Result from_estimate =
      run("predict --estimate " + dir + "/est/estimate.json --data " + train + " --out " + dir +
          "/estimate");
  ASSERT_EQ(from_estimate.code, 0) << from_estimate.err;
  const auto w = nlohmann::json::parse(readFile(dir + "/written/prediction.json"));
  const auto e = nlohmann::json::parse(readFile(dir + "/estimate/prediction.json"));
  // 1e-6 relative: the URDF's numbers are written with 17 significant digits, the estimate's
  // prediction uses the same parameters in memory.
  EXPECT_NEAR(w["relative_error"].get<double>(), e["relative_error"].get<double>(),
              1e-6 * e["relative_error"].get<double>() + 1e-12);
  // One naming of the per-joint errors in every document: estimate.json's fit and held-out
  // validation, prediction.json.
  ASSERT_EQ(run("identify --method pc --robot " + urdf + " --data " + train + " --validate " +
                train + " --out " + dir + "/validated")
                .code,
            0);
  const auto v = nlohmann::json::parse(readFile(dir + "/validated/estimate.json"));
  for (const char* key : {"residual_rms", "joint_relative_error", "relative_error"}) {
    EXPECT_TRUE(v.contains(key)) << key;
    EXPECT_TRUE(v["validation"].contains(key)) << key;
    EXPECT_TRUE(w.contains(key)) << key;
  }
  // Usage: neither, and drive options beside an estimate.
  EXPECT_EQ(run("predict --data " + train + " --out " + dir + "/x").code, 2);
  EXPECT_EQ(run("predict --estimate " + dir + "/est/estimate.json --drives --data " + train +
                " --out " + dir + "/x")
                .code,
            2);
}

}  // namespace
}  // namespace dynid
