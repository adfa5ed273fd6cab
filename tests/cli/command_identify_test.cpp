// dynid identify: OLS, WLS and pc estimates from simulated data.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "tests/common/cli.hpp"
#include "tests/common/panda_log.hpp"
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
  // --rest-velocity 0: simulate's friction is Fc sign(dq) at every speed (no stiction), so its
  // noiseless joints dither at reversals with the friction flipping; that truth is the model of
  // dynid 0.1, which a rest velocity measured from the dither would not predict.
  const Result r = run("identify --method wls --robot puma560 --drives --data " + train +
                       " --validate " + test_csv + " --rest-velocity 0 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/estimate.json"));
  EXPECT_EQ(j["method"], "wls");
  EXPECT_EQ(j["num_base"], 58);
  const auto& p = j["base_parameters"][0];
  for (const char* key : {"name", "expression", "estimate", "std_dev", "relative_std_dev_percent"})
    EXPECT_TRUE(p.contains(key)) << key;
  ASSERT_EQ(j["validation"]["residual_rms"].size(), 6u);
  // 0.01 N m torque noise: the held-out prediction error stays of that order.
  for (const auto& rms : j["validation"]["residual_rms"]) EXPECT_LT(rms.get<double>(), 0.05);
  EXPECT_TRUE(
      contains(readFile(dir + "/report.md"), "| joint | measured RMS [N m] | residual RMS"));
  EXPECT_TRUE(contains(readFile(dir + "/report.html"), "<figure id=\"torques_validate\">"));
  // The covariance: hac by default, named in estimate.json, the console and the report; the
  // white one on request, with the same estimate. White noise: the two agree in the median over
  // the parameters; each parameter's hac variance has the random error of the batches that see it
  // (250 batches of 16 samples, but a parameter this 4 s motion excites in a few of them has a
  // variance of few degrees of freedom: its standard deviation within a factor 2).
  EXPECT_EQ(j["base_covariance"]["policy"]["name"], "hac");
  EXPECT_TRUE(contains(r.out, "intervals: robust to correlated residuals, over")) << r.out;
  EXPECT_TRUE(
      contains(readFile(dir + "/report.md"), "Uncertainty: intervals: robust to correlated"));
  const std::string white_dir = test::tempPath("estimate-white");
  const Result white = run("identify --method wls --robot puma560 --drives --data " + train +
                           " --rest-velocity 0 --covariance white --out " + white_dir);
  ASSERT_EQ(white.code, 0) << white.err;
  const auto w = nlohmann::json::parse(readFile(white_dir + "/estimate.json"));
  EXPECT_EQ(w["base_covariance"]["policy"]["name"], "white");
  EXPECT_TRUE(contains(white.out, "intervals: the white covariance")) << white.out;
  const double inflation = j["base_covariance"]["policy"]["inflation"].get<double>();
  EXPECT_GT(inflation, 0.85);
  EXPECT_LT(inflation, 1.2);
  for (std::size_t k = 0; k < w["base_parameters"].size(); ++k) {
    EXPECT_EQ(w["base_parameters"][k]["estimate"], j["base_parameters"][k]["estimate"]) << k;
    const double ratio = j["base_parameters"][k]["std_dev"].get<double>() /
                         w["base_parameters"][k]["std_dev"].get<double>();
    EXPECT_GT(ratio, 0.5) << k;
    EXPECT_LT(ratio, 2.0) << k;
  }
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

// identify --method combined --no-gc-floor: the GC term is fitted below its noise floor (the
// noise fitted, docs/REFINEMENT.md); by default it is held at the floor, where pc already is on
// this noisy log.
// identify on a prepare output reproduces its torque's low-pass on the friction columns (from
// the prepare.json beside the data), says so, records it in estimate.json, which predict reads
// back; --torque-filter none takes the torque as unfiltered.
TEST(Cli, IdentifyReproducesPreparesTorqueFilter) {
  const std::string dir = test::tempPath("cli_torque_filter");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("simulate --robot puma560 --drives --controller fourier --duration 20 --seed 5 "
                "--noise-q 1e-5 --noise-tau 0.5 --out " +
                dir + "/sim.csv")
                .code,
            0);
  ASSERT_EQ(
      run("prepare --log " + dir + "/sim.csv --q 'q*' --tau 'tau*' --out " + dir + "/prep").code,
      0);
  const Result r = run("identify --robot puma560 --drives --data " + dir +
                       "/prep/train.csv --out " + dir + "/id");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "rows fitted per joint:")) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "order-4 Butterworth at 10 Hz (zero phase), sampled at 1000 Hz "
                       "(prepare.json: the torque's low-pass)"))
      << r.out;
  const auto estimate = nlohmann::json::parse(readFile(dir + "/id/estimate.json"));
  EXPECT_EQ(estimate["schema_version"], 8);
  const auto& rows = estimate["fit_rows"];
  EXPECT_EQ(rows["torque_filter"]["cutoff_hz"], 10.0);
  EXPECT_EQ(rows["torque_filter"]["order"], 4);
  EXPECT_GT(rows["torque_filter"]["reach_samples"].get<int>(), 100);
  for (const auto& fitted : rows["rows"]) {
    EXPECT_LT(fitted.get<double>(), estimate["data"]["samples"].get<double>());
    EXPECT_GT(fitted.get<double>(), 0.3 * estimate["data"]["samples"].get<double>());
  }
  EXPECT_EQ(run("predict --estimate " + dir + "/id/estimate.json --data " + dir +
                "/prep/train.csv --out " + dir + "/predict")
                .code,
            0);
  const Result none = run("identify --robot puma560 --drives --torque-filter none --data " + dir +
                          "/prep/train.csv --out " + dir + "/id_none");
  ASSERT_EQ(none.code, 0) << none.err;
  const auto plain = nlohmann::json::parse(readFile(dir + "/id_none/estimate.json"));
  EXPECT_TRUE(plain["fit_rows"]["torque_filter"].is_null());
  EXPECT_EQ(plain["fit_rows"]["torque_filter_source"], "none: given");
  EXPECT_NE(plain["base_parameters"][2]["estimate"], estimate["base_parameters"][2]["estimate"]);
  // The same filtered data without its prepare.json: the note on reversals says how to give the
  // filter, in this command's flag.
  std::filesystem::copy_file(dir + "/prep/train.csv", dir + "/alone.csv");
  const Result alone =
      run("identify --robot puma560 --drives --data " + dir + "/alone.csv --out " + dir + "/id2");
  ASSERT_EQ(alone.code, 0) << alone.err;
  EXPECT_TRUE(contains(alone.out,
                       "reads as missing friction: --torque-filter (its cutoff and "
                       "order) makes the fit reproduce it"))
      << alone.out;
  EXPECT_FALSE(contains(alone.out, "`torque_filter`")) << alone.out;
}

TEST(Cli, CombinedWithoutTheGcFloorFitsBelowIt) {
  const std::string train = test::tempPath("floor_train.csv");
  ASSERT_EQ(run("simulate --robot puma560 --duration 6 --amplitude 1 --q0 0,0.8,1.5,0,0.8,0 "
                "--frequency 0.23,0.31,0.41,0.53,0.61,0.71 --bandwidth 8 --noise-tau 0.2 --seed 2 "
                "--out " +
                train)
                .code,
            0);
  auto combined = [&](const std::string& extra) {
    const std::string dir = test::tempPath("floor_combined");
    // Two iterations and no time budget: the same steps on any machine (the sanitizer build's
    // 60 s budget ended it after one).
    const Result r =
        run("identify --method combined --combined-iterations 2 --combined-seconds 0 --robot "
            "puma560 --data " +
            train + " --out " + dir + extra);
    EXPECT_EQ(r.code, 0) << r.err;
    return nlohmann::json::parse(readFile(dir + "/estimate.json"))["combined"];
  };
  const auto held = combined("");
  const double floor = held["gc_noise_floor"].get<double>();
  const double pc = held["gc_error_train"]["pc"].get<double>();
  ASSERT_GT(floor, pc);  // this log's GC error is noise already at pc
  // Held at the floor: pc's GC error stays, to the estimator's tolerance (1e-6 relative per
  // step, a few steps).
  EXPECT_NEAR(held["gc_error_train"]["combined"].get<double>(), pc, 1e-4 * pc);
  const auto fitted = combined(" --no-gc-floor");
  EXPECT_EQ(fitted["gc_noise_floor"].get<double>(), 0.0);
  // Below the floor by far (331.6 against 5385 when written): the noise fitted.
  EXPECT_LT(fitted["gc_error_train"]["combined"].get<double>(), 0.1 * floor);
  const Result other = run("identify --method pc --no-gc-floor --robot puma560 --data " + train +
                           " --out " + test::tempPath("floor_pc"));
  EXPECT_EQ(other.code, 2);
  EXPECT_TRUE(contains(other.err, "--no-gc-floor applies to --method combined")) << other.err;
}

TEST(Cli, WriteUrdfReloadsToTheEstimatesTorques) {
  const std::string urdf = test::tempPath("arm.urdf"), train = test::tempPath("arm_train.csv"),
                    out = test::tempPath("arm_estimate"), written = test::tempPath("arm_pc.urdf");
  ASSERT_EQ(
      run("model export --robot puma560-consistent --drives --format urdf --out " + urdf).code, 0);
  const std::string robot = " --robot " + urdf + " --drive-terms fv,fc";
  // Data from the built-in robot with its rotors (without them the wrist is too stiff to simulate).
  ASSERT_EQ(run("simulate --robot puma560-consistent --drives"
                " --duration 4 --amplitude 1 --q0 0,0.8,1.5,0,0.8,0 --frequency "
                "0.23,0.31,0.41,0.53,0.61,0.71 --bandwidth 8 --noise-tau 0.01 --seed 5 --out " +
                train)
                .code,
            0);
  const Result r = run("identify --method pc" + robot + " --data " + train + " --out " + out +
                       " --write-urdf " + written);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "directions the data cannot see come from the input model")) << r.out;
  EXPECT_FALSE(contains(r.out, "URDF has no place")) << r.out;  // Fv and Fc go in <dynamics>
  // Rotor inertias have no place in a URDF: said, with their values, and the JSON named.
  const std::string with_rotors = test::tempPath("arm_rotors.urdf");
  const Result rotors =
      run("identify --method pc --robot " + urdf + " --drive-terms ia,fv,fc" + " --data " + train +
          " --out " + test::tempPath("arm_rotors") + " --write-urdf " + with_rotors);
  ASSERT_EQ(rotors.code, 0) << rotors.err;
  EXPECT_TRUE(contains(rotors.out,
                       "note: URDF has no place for rotor inertias, offsets or other "
                       "drive terms: " +
                           with_rotors + " goes without Ia1 "))
      << rotors.out;
  EXPECT_TRUE(contains(rotors.out, "arm_rotors.dynid.json carries them")) << rotors.out;
  const std::string json_beside = written.substr(0, written.size() - 5) + ".dynid.json";
  ASSERT_TRUE(std::filesystem::exists(json_beside));
  // The estimate's predicted torques: its standard parameters in the input robot.
  RobotOptions terms;
  terms.drive_terms = parseDriveTerms("fv,fc");
  Model estimate = loadRobot(urdf, terms);
  const auto report = nlohmann::json::parse(readFile(out + "/estimate.json"));
  EXPECT_GT(report["write_back"]["unseen_directions"].get<int>(), 0);  // said in the report too
  const auto& values = report["standard_estimate"]["values"];
  const std::vector<std::string> names = standardParameterNames(estimate.parameterLayout());
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k)
    theta[static_cast<Eigen::Index>(k)] = values[names[k]];
  estimate.setStandardParameters(theta);
  const Model reloaded = loadRobot(written, terms), beside = loadRobot(json_beside);
  const Trajectory data = readDatasetCsv(train, 6);
  Data a(estimate), b(reloaded), c(beside);
  double worst = 0.0, worst_json = 0.0;
  for (int k = 0; k < data.numSamples(); k += 10) {
    const Eigen::VectorXd q = data.q.col(k), dq = data.dq.col(k), ddq = data.ddq.col(k);
    const Eigen::VectorXd tau = rnea(estimate, a, q, dq, ddq);
    worst = std::max(worst, (rnea(reloaded, b, q, dq, ddq) - tau).norm() / tau.norm());
    worst_json = std::max(worst_json, (rnea(beside, c, q, dq, ddq) - tau).norm() / tau.norm());
  }
  EXPECT_LT(worst, 1e-9);       // the bound: decimal round trips of the parameters
  EXPECT_LT(worst_json, 1e-9);  // the JSON beside carries the same model
  // The written URDF as docs/TOUR.md uses it, without drive options: its <dynamics> read back as
  // Fv and Fc, said, and the estimate's own prediction again (the URDF's decimals: 1e-6).
  const std::string by_urdf = test::tempPath("arm_pc_predict"),
                    by_estimate = test::tempPath("arm_pc_predict_estimate");
  const Result back = run("predict --robot " + written + " --data " + train + " --out " + by_urdf);
  ASSERT_EQ(back.code, 0) << back.err;
  EXPECT_TRUE(contains(back.err, "read as viscous and Coulomb friction")) << back.err;
  EXPECT_TRUE(contains(back.err, "--drive-terms none gives the rigid model")) << back.err;
  ASSERT_EQ(
      run("predict --estimate " + out + "/estimate.json --data " + train + " --out " + by_estimate)
          .code,
      0);
  const double urdf_error =
      nlohmann::json::parse(readFile(by_urdf + "/prediction.json"))["relative_error"];
  const double estimate_error =
      nlohmann::json::parse(readFile(by_estimate + "/prediction.json"))["relative_error"];
  EXPECT_NEAR(urdf_error, estimate_error, 1e-6 * estimate_error);
  // Refused, nothing written: a robot that is not a URDF (usage), an unwritable path, an
  // inconsistent OLS estimate (the published PUMA's links 1 and 3 as the prior).
  const std::string not_written = test::tempPath("never");
  EXPECT_EQ(run("identify --robot puma560 --data " + train + " --out " + not_written +
                " --write-urdf " + test::tempPath("x.urdf"))
                .code,
            2);
  const Result unwritable = run("identify --method pc" + robot + " --data " + train + " --out " +
                                not_written + " --write-urdf /nonexistent-dir/x.urdf");
  EXPECT_EQ(unwritable.code, 2);  // refused before the work
  EXPECT_TRUE(contains(unwritable.err,
                       "--write-urdf: the directory '/nonexistent-dir' does not "
                       "exist"))
      << unwritable.err;
  // Into --out's own directory, new: written there beside the estimate.
  const std::string fresh = test::tempPath("fresh_out");
  const Result inside = run("identify --method pc" + robot + " --data " + train + " --out " +
                            fresh + " --write-urdf " + fresh + "/arm.urdf");
  EXPECT_EQ(inside.code, 0) << inside.err;
  EXPECT_TRUE(std::filesystem::exists(fresh + "/arm.urdf"));
  EXPECT_TRUE(std::filesystem::exists(fresh + "/arm.dynid.json"));
  EXPECT_TRUE(std::filesystem::exists(fresh + "/estimate.json"));
  const std::string published = test::tempPath("published.urdf");
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + published).code, 0);
  const Result ols = run("identify --method ols --robot " + published + " --data " + train +
                         " --out " + not_written + " --write-urdf " + test::tempPath("y.urdf"));
  EXPECT_EQ(ols.code, 1);
  EXPECT_TRUE(contains(ols.err, "use --method pc")) << ols.err;
  EXPECT_FALSE(std::filesystem::exists(not_written));
  EXPECT_FALSE(std::filesystem::exists(test::tempPath("y.urdf")));
  // The input URDF (or its .dynid.json companion) as the target: refused before any work, the
  // input untouched; and a companion that cannot be written deletes nothing.
  const std::string before = readFile(urdf);
  const Result onto_input = run("identify --method pc" + robot + " --data " + train + " --out " +
                                not_written + " --write-urdf " + urdf);
  EXPECT_EQ(onto_input.code, 2);
  EXPECT_TRUE(contains(onto_input.err, "is an input of this command")) << onto_input.err;
  EXPECT_EQ(readFile(urdf), before);
  const std::string blocked = test::tempPath("blocked.urdf");
  std::filesystem::create_directories(blocked.substr(0, blocked.size() - 5) +
                                      ".dynid.json");  // a directory: not writable
  writeFileAtomically(blocked, "an earlier write-back");
  const Result half = run("identify --method pc" + robot + " --data " + train + " --out " +
                          not_written + " --write-urdf " + blocked);
  EXPECT_EQ(half.code, 1);
  EXPECT_EQ(readFile(blocked), "an earlier write-back");  // neither written nor deleted
}

TEST(Cli, IdentifiesTheRealPandaLogWithItsPublishedModel) {
  // Gaz et al.'s log, built into a dataset here (dynid prepare is the next step): every 10th
  // sample, derivatives from local cubic fits over +-50 ms on the real time stamps.
  const std::string dir = test::pandaLogDirectory();
  if (dir.empty()) GTEST_SKIP() << "the Panda log is not beside the repository";
  const std::string csv = test::tempPath("panda_log.csv");
  writeDatasetCsv(csv, test::pandaLogTrajectory(dir, 10, 0.05));
  const std::string robot = " --robot panda --drive-terms fv,fc,fo --data " + csv;
  const std::string ols_dir = test::tempPath("panda_ols"), pc_dir = test::tempPath("panda_pc");
  const Result ols = run("identify --method ols" + robot + " --out " + ols_dir);
  ASSERT_EQ(ols.code, 0) << ols.err;
  const auto o = nlohmann::json::parse(readFile(ols_dir + "/estimate.json"));
  // Gaz et al.: 43 inertial + 21 friction base parameters.
  EXPECT_EQ(o["num_base"], 64);
  // Both condition numbers and the relative error on the console, each labelled.
  EXPECT_TRUE(contains(ols.out, "(unscaled)") && contains(ols.out, "(unit columns)")) << ols.out;
  EXPECT_TRUE(contains(ols.out, "relative torque error")) << ols.out;
  // Published: 121.88 on their filtered data; an independent computation on this log's 64
  // columns gives 109. Measured here: 109.3.
  const double cond = o["condition_number_unscaled"];
  EXPECT_GT(cond, 100.0);
  EXPECT_LT(cond, 125.0);
  // Published 1.41 %; within 0.2 percentage points of it (their filtering differs from the local
  // fits here). Measured: 1.536 %.
  const double ols_error = o["relative_error"];
  EXPECT_LT(std::abs(ols_error - 0.0141), 0.002) << ols_error;

  const Result pc = run("identify --method pc" + robot + " --out " + pc_dir);
  ASSERT_EQ(pc.code, 0) << pc.err;
  EXPECT_FALSE(contains(pc.err, "warning")) << pc.err;  // converged: no cap warning
  const auto p = nlohmann::json::parse(readFile(pc_dir + "/estimate.json"));
  const std::string termination = p["physically_consistent"]["termination"];
  EXPECT_EQ(termination.rfind("CONVERGENCE", 0), 0u) << termination;
  // The bound: pc within 0.2 percentage points of OLS. Measured: 1.576 % against 1.536 %.
  const double pc_error = p["relative_error"];
  EXPECT_LT(pc_error - ols_error, 0.002) << pc_error;
  // Every link physically consistent (what dynid model check tests).
  const auto& values = p["standard_estimate"]["values"];
  for (int i = 1; i <= 7; ++i) {
    const std::string n = std::to_string(i);
    Eigen::Matrix<double, 10, 1> link;
    for (int k = 0; k < 10; ++k) link[k] = values[std::string(kLinkParameterNames[k]) + n];
    EXPECT_TRUE(checkPhysicalConsistency(fromStandardVector(link), i - 1, "link" + n).empty())
        << "link " << i;
  }
}

TEST(Cli, PandaExampleRunsAndBeatsThePublishedFit) {
  const std::string dir = test::pandaLogDirectory();
  if (dir.empty()) GTEST_SKIP() << "the Panda log is not beside the repository";
  const std::string out = test::tempPath("panda_example");
  const std::string script = std::string(DYNID_SOURCE_DIR) + "/examples/panda/run.sh";
  const int code = std::system(
      ("bash " + script + " " + DYNID_BIN + " " + dir + " " + out + " > " + out + ".log 2>&1")
          .c_str());
  ASSERT_EQ(code, 0) << readFile(out + ".log");
  const auto ols = nlohmann::json::parse(readFile(out + "/ols/estimate.json"));
  const auto pc = nlohmann::json::parse(readFile(out + "/pc/estimate.json"));
  EXPECT_EQ(ols["num_base"], 64);
  // The published OLS fit is 1.41 %; the example's is 0.914 % (train) and 0.939 % (held out),
  // the filter reproduced on the friction columns (1.018 % and 1.022 % before, docs/MODEL.md).
  EXPECT_LE(ols["relative_error"].get<double>(), 0.0141);
  EXPECT_LE(ols["validation"]["relative_error"].get<double>(), 0.0141);
  // pc within 0.2 percentage points of OLS, converged.
  EXPECT_LT(pc["relative_error"].get<double>() - ols["relative_error"].get<double>(), 0.002);
  const std::string termination = pc["physically_consistent"]["termination"];
  EXPECT_EQ(termination.rfind("CONVERGENCE", 0), 0u) << termination;
  EXPECT_TRUE(std::filesystem::exists(out + "/panda_identified.urdf"));
  // The report: measured against predicted torque for all 7 joints, training and held out, and
  // the preprocessing that made the data.
  const std::string html = readFile(out + "/ols/report.html");
  for (const char* figure : {"torques_train", "torques_validate", "residuals"})
    EXPECT_NE(html.find("<figure id=\"" + std::string(figure) + "\">"), std::string::npos)
        << figure;
  for (int j = 1; j <= 7; ++j)
    EXPECT_NE(html.find("tau" + std::to_string(j) + " [N m]"), std::string::npos) << j;
  EXPECT_NE(html.find("Preprocessing (dynid prepare)"), std::string::npos);
  // Friction at reversals: joint 7 has more than half of its squared training residual on about
  // 6 % of the samples (measured: 60 % on 6.1 %), and the note proposes the Stribeck term and
  // says the residual is not the filter's artefact (the fit reproduced it).
  const auto& reversals = ols["reversals"];
  const std::vector<int> flagged = reversals["flagged"];
  EXPECT_NE(std::find(flagged.begin(), flagged.end(), 7), flagged.end()) << reversals.dump();
  EXPECT_GT(reversals["residual_share"][6].get<double>(), 0.5) << reversals.dump();
  const std::string log = readFile(out + ".log");
  EXPECT_TRUE(contains(log, "note: friction at reversals:") &&
              contains(log, "--drive-terms fv,fc,fo,fs adds Stribeck") &&
              contains(log, "not the torque filter's artefact"))
      << log;
  EXPECT_TRUE(contains(html, "friction at reversals")) << "the report's note";
  // predict measures the same on the data it is given (the example's held-out part).
  const auto prediction = nlohmann::json::parse(readFile(out + "/predict/prediction.json"));
  EXPECT_GT(prediction["reversals"]["samples"].get<int>(), 3000) << prediction["reversals"];
  EXPECT_EQ(prediction["reversals"]["residual_share"].size(), 7u);
  // Which it barely does, once the filter is reproduced: the held-out error moves by 0.4 %
  // (measured: 0.9354 % against 0.9393 %; with the filter's artefact in the fit, Stribeck had
  // seemed to help, 0.962 % against 1.022 %).
  const std::string fs_dir = test::tempPath("panda_fs");
  const Result fs = run("identify --robot panda --drive-terms fv,fc,fo,fs --data " + out +
                        "/data/train.csv --validate " + out + "/data/validate.csv --out " + fs_dir);
  ASSERT_EQ(fs.code, 0) << fs.err;
  const auto with_fs = nlohmann::json::parse(readFile(fs_dir + "/estimate.json"));
  EXPECT_NEAR(with_fs["validation"]["relative_error"].get<double>(),
              ols["validation"]["relative_error"].get<double>(), 0.0003);
  // With fs among the terms, what is still flagged is said to be beyond them.
  if (!with_fs["reversals"]["flagged"].empty()) {
    EXPECT_TRUE(contains(fs.out, "is beyond the drive terms")) << fs.out;
  }
}

// identify --method combined --front: the front's points on the held-out data in estimate.json,
// the estimate the point the rule takes; the options refused where they do not apply.
TEST(Cli, IdentifyFrontTakesThePointTheHeldOutDataChoose) {
  const auto [train, held] = test::noisyPumaPair("idfront");
  ASSERT_FALSE(train.empty());
  const std::string dir = test::tempPath("idfront");
  const std::string common =
      "identify --method combined --robot puma560 --drive-terms fv,fc "
      "--data " +
      train + " --segments 8 --combined-iterations 3 ";
  const Result r =
      run(common + "--validate " + held + " --front-weights 0.3,3 --threads 2 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "the front: 2 points")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/estimate.json"));
  EXPECT_EQ(j["schema_version"], 8);
  const auto& points = j["front"]["points"];
  ASSERT_EQ(points.size(), 2u);
  // The rule, recomputed from the recorded errors: within 5 % of the least held-out torque error,
  // the least held-out GC error above its noise floor (at the floor, within 10 % of it: 0), ties
  // to the least torque error.
  const auto torque = [&](int k) { return points[k]["torque_relative_error_test"].get<double>(); };
  const auto excess = [&](int k) {
    const double gc = points[k]["gc_error_test"].get<double>();
    const double floor = points[k]["gc_noise_floor_test"].get<double>();
    return gc <= 1.1 * floor ? 0.0 : gc - floor;
  };
  const double best = std::min(torque(0), torque(1));
  int chosen = -1;
  for (int k = 0; k < 2; ++k)
    if (torque(k) <= 1.05 * best && (chosen < 0 || excess(k) < excess(chosen) ||
                                     (excess(k) == excess(chosen) && torque(k) < torque(chosen))))
      chosen = k;
  EXPECT_GT(points[0]["gc_noise_floor_test"].get<double>(), 0.0);  // each point's floor recorded
  EXPECT_EQ(j["front"]["chosen_weight"], points[chosen]["weight"]);
  // The estimate is that point: its held-out errors are the estimate's own.
  EXPECT_DOUBLE_EQ(j["validation"]["relative_error"].get<double>(),
                   points[chosen]["torque_relative_error_test"].get<double>());
  EXPECT_DOUBLE_EQ(j["combined"]["gc_error_test"]["combined"].get<double>(),
                   points[chosen]["gc_error_test"].get<double>());
  EXPECT_TRUE(contains(readFile(dir + "/report.md"), "## The front, and the estimate chosen"));
  // Refused before any work: no held-out data, another method, a weight with the sweep.
  const std::string none = test::tempPath("idfront_never");
  for (const std::string& bad :
       {common + "--front --out " + none,
        common + "--validate " + held + " --front --combined-weight 3 --out " + none,
        "identify --method pc --robot puma560 --data " + train + " --validate " + held +
            " --front --out " + none}) {
    const Result refused = run(bad);
    EXPECT_EQ(refused.code, 2) << bad;
    EXPECT_TRUE(contains(refused.err, "--front") || contains(refused.err, "--combined-weight"))
        << refused.err;
  }
  EXPECT_FALSE(std::filesystem::exists(none));
}

}  // namespace
}  // namespace dynid
