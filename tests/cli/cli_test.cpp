// The dynid executable end to end: exit codes (0 ok, 1 runtime or data error, 2 usage error),
// messages that name the file, row or field, JSON output, and files written whole or not at all.
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
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

Result run(const std::string& args) {
  const std::string out = test::tempPath("stdout"), err = test::tempPath("stderr");
  const int status =
      std::system((std::string(DYNID_BIN) + " " + args + " >" + out + " 2>" + err).c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

bool contains(const std::string& s, const std::string& fragment) {
  return s.find(fragment) != std::string::npos;
}

TEST(Cli, VersionHelpAndUsage) {
  EXPECT_EQ(run("--version").code, 0);
  EXPECT_TRUE(contains(run("--help").out, "commands:"));
  EXPECT_EQ(run("").code, 2);
  const Result unknown = run("fly");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_TRUE(contains(unknown.err, "unknown command 'fly'"));
  for (const char* command : {"dynamics", "simulate", "model show", "model check", "model export",
                              "identifiability", "identify", "search", "refine"}) {
    const Result help = run(std::string(command) + " --help");
    EXPECT_EQ(help.code, 0) << command;
    EXPECT_TRUE(contains(help.out, "usage: dynid")) << command;
  }
}

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

TEST(Cli, UsageErrorsNameTheOption) {
  Result r = run("dynamics --robot puma560 --q 1,2");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--q has 2 entries, the robot has 6 joints")) << r.err;
  r = run("dynamics --robot puma560 --dq 1,x,0,0,0,0");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--dq: entry 2 'x' is not a finite number")) << r.err;
  r = run("dynamics --robot puma560 --ddq 0,0,0,0,0,0 --tau 0,0,0,0,0,0");
  EXPECT_EQ(r.code, 2);
  r = run("dynamics --q 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "--robot")) << r.err;
  r = run("simulate --robot puma560 --out x.csv --integrator rk45");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(contains(r.err, "unknown integrator 'rk45'")) << r.err;
  r = run("model export --robot puma560 --format sdf --out x");
  EXPECT_EQ(r.code, 2);
}

TEST(Cli, DataErrorsNameTheFile) {
  const Result r = run("dynamics --robot /nonexistent/arm.urdf");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, "/nonexistent/arm.urdf")) << r.err;
  const std::string bad = test::tempPath("bad.urdf");
  std::ofstream(bad)
      << "<robot name='x'><link name='a'/><link name='b'><inertial><mass value='-1'/>"
         "<inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link>"
         "<joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
         "<limit lower='-1' upper='1' effort='1' velocity='1'/></joint></robot>";
  const Result urdf = run("model show --robot " + bad);
  EXPECT_EQ(urdf.code, 1);
  EXPECT_TRUE(contains(urdf.err, bad + ":1: link 'b': negative mass")) << urdf.err;
  // A massless moving link: loads with a warning, and its dynamics are reported singular.
  const std::string massless = test::tempPath("massless.urdf");
  std::ofstream(massless) << "<robot name='x'><link name='a'/><link name='b'/>"
                             "<joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
                             "</joint></robot>";
  const Result singular = run("dynamics --robot " + massless + " --tau 1");
  EXPECT_EQ(singular.code, 1);
  EXPECT_TRUE(contains(singular.err, "warning: " + massless + ": link 'b' has no <inertial>"))
      << singular.err;
  EXPECT_TRUE(contains(singular.err, "singular")) << singular.err;
}

TEST(Cli, SimulateWritesADatasetAndSummary) {
  const std::string path = test::tempPath("sim.csv");
  const Result r =
      run("simulate --robot puma560 --duration 0.5 --noise-q 1e-4 --seed 3 --out " + path);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "501 samples x 6 joints")) << r.out;
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.substr(0, 8), "t,q1,q2,");
  // Same seed, same file; the Fourier controller runs too.
  const std::string again = test::tempPath("sim2.csv");
  ASSERT_EQ(
      run("simulate --robot puma560 --duration 0.5 --noise-q 1e-4 --seed 3 --out " + again).code,
      0);
  EXPECT_EQ(readFile(path), readFile(again));
  EXPECT_EQ(
      run("simulate --robot puma560 --drives --controller fourier --duration 0.2 --out " + again)
          .code,
      0);
}

TEST(Cli, FailedWritesLeaveNoPartialFile) {
  const std::string dir = test::tempPath("no-such-dir");
  const Result r = run("simulate --robot puma560 --duration 0.1 --out " + dir + "/sim.csv");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(contains(r.err, dir + "/sim.csv")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  const Result bad_rate =
      run("simulate --robot puma560 --dt 3e-4 --out " + test::tempPath("x.csv"));
  EXPECT_EQ(bad_rate.code, 1);
  EXPECT_TRUE(contains(bad_rate.err, "not a whole multiple")) << bad_rate.err;
}

TEST(Cli, ModelExportAndReload) {
  const std::string json = test::tempPath("puma.json"), urdf = test::tempPath("puma.urdf");
  ASSERT_EQ(run("model export --robot puma560 --drives --format json --out " + json).code, 0);
  ASSERT_EQ(run("model export --robot puma560 --format urdf --out " + urdf).code, 0);
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
}

TEST(Cli, IdentifiabilityReport) {
  const std::string dir = test::tempPath("ident");
  const Result r = run("identifiability --robot puma560 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "60 standard parameters, 36 base parameters")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/identifiability.json"));
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["robot"], "puma560");
  EXPECT_EQ(j["num_standard"], 60);
  EXPECT_EQ(j["num_base"], 36);
  EXPECT_GT(j["rank_gap"].get<double>(), 1e8);
  ASSERT_EQ(j["base_parameters"].size(), 36u);
  for (const char* key : {"name", "expression", "coefficients"})
    EXPECT_TRUE(j["base_parameters"][0].contains(key)) << key;
  EXPECT_EQ(j["unidentifiable"].size(), 9u);
  EXPECT_EQ(j["null_space"]["basis"].size(), 24u);
  EXPECT_TRUE(j["condition_number"].is_number());
  const std::string md = readFile(dir + "/identifiability.md");
  EXPECT_TRUE(contains(md, "| 36 | Izz6 | `Izz6` |")) << md;
}

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

TEST(Cli, SearchWritesHistoryAndResumesFromACheckpoint) {
  const std::string train = test::tempPath("search_train.csv"), dir = test::tempPath("search");
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + train).code, 0);
  const std::string common = "search --robot puma560 --data " + train +
                             " --perturb 0.3 --truth puma560 --seed 1 --segments 20 --threads 2 ";
  const Result r = run(common + "--method ga --population 10 --budget-evals 60 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(dir + "/search.json"));
  for (const char* key :
       {"schema_version", "method", "settings", "initial_gc_error", "final_gc_error", "estimate",
        "history", "evaluations", "seconds", "termination", "final_parameter_error"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["termination"], "evaluations");
  EXPECT_LE(j["final_gc_error"].get<double>(), j["initial_gc_error"].get<double>());
  EXPECT_EQ(j["estimate"]["paper"].size(), 42u);
  EXPECT_EQ(j["estimate"]["standard"].size(), 60u);
  EXPECT_TRUE(j["history"][0].contains("min_parameter_error"));
  // A run stopped at 30 evaluations and resumed to 60 ends exactly where the single run did.
  const std::string checkpoint = test::tempPath("search.ckpt"), resumed = test::tempPath("resumed");
  ASSERT_EQ(run(common + "--method ga --population 10 --budget-evals 30 --checkpoint " +
                checkpoint + " --out " + resumed)
                .code,
            0);
  ASSERT_EQ(run(common + "--method ga --population 10 --budget-evals 60 --checkpoint " +
                checkpoint + " --out " + resumed)
                .code,
            0);
  const auto k = nlohmann::json::parse(readFile(resumed + "/search.json"));
  EXPECT_EQ(k["final_gc_error"], j["final_gc_error"]);
  EXPECT_EQ(k["evaluations"], j["evaluations"]);
  EXPECT_EQ(k["estimate"], j["estimate"]);
  // Settings that change the search itself must match.
  const Result refused =
      run(common + "--method ga --population 12 --budget-evals 60 --checkpoint " + checkpoint +
          " --out " + resumed);
  EXPECT_EQ(refused.code, 1);
  EXPECT_TRUE(contains(refused.err, "other settings")) << refused.err;
}

TEST(Cli, RefineFromASearchAndFromAnEstimate) {
  const std::string train = test::tempPath("refine_train.csv"), dir = test::tempPath("refine_s"),
                    refined = test::tempPath("refined");
  ASSERT_EQ(run("simulate --robot puma560 --duration 2 --out " + train).code, 0);
  ASSERT_EQ(run("search --method ga --robot puma560 --data " + train +
                " --perturb 0.1 --truth puma560 --seed 1 --segments 10 --threads 2 --population 10 "
                "--budget-evals 20 --out " +
                dir)
                .code,
            0);
  const Result r = run("refine --robot puma560 --from " + dir + "/search.json --data " + train +
                       " --truth puma560 --max-iterations 5 --threads 2 --out " + refined);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(readFile(refined + "/refine.json"));
  for (const char* key :
       {"schema_version", "estimate", "cost_history", "termination", "solution_usable",
        "base_parameters", "identifiability", "final_base_parameter_error", "parameters_at_bound"})
    EXPECT_TRUE(j.contains(key)) << key;
  // The search's settings carry over: 10 segments, the same free parameters.
  EXPECT_EQ(j["settings"]["segments"], 10);
  const auto s = nlohmann::json::parse(readFile(dir + "/search.json"));
  EXPECT_EQ(j["settings"]["free_parameters"], s["settings"]["free_parameters"]);
  EXPECT_LT(j["final_gc_error"].get<double>(), j["initial_gc_error"].get<double>());
  EXPECT_EQ(j["base_parameters"]["values"].size(), 36u);
  EXPECT_EQ(j["base_parameters"]["covariance"].size(), 36u);
  EXPECT_FALSE(j["identifiability"]["free_directions"].empty());
  // Both stages' iterations (0 .. N each) are in the history, base coordinates first.
  EXPECT_TRUE(j["base_stage"]["run"].get<bool>());
  EXPECT_EQ(j["cost_history"].size(), j["base_stage"]["iterations"].get<std::size_t>() + 1 +
                                          j["iterations"].get<std::size_t>() + 1);
  EXPECT_EQ(j["cost_history"].front()["stage"], "base");
  EXPECT_EQ(j["cost_history"].back()["stage"], "parameters");
  EXPECT_TRUE(j["base_stage"].contains("base_parameter_error"));
  // From an identify estimate (physically consistent), estimating the starts too.
  const std::string estimate = test::tempPath("pc_estimate");
  const Result pc =
      run("identify --method pc --robot puma560 --data " + train + " --out " + estimate);
  ASSERT_EQ(pc.code, 0) << pc.err;
  const auto e = nlohmann::json::parse(readFile(estimate + "/estimate.json"));
  EXPECT_EQ(e["method"], "pc");
  EXPECT_TRUE(e["physically_consistent"]["solution_usable"].get<bool>());
  const Result from_estimate = run(
      "refine --robot puma560 --from " + estimate + "/estimate.json --data " + train +
      " --segments 10 --estimate-initial-states --max-iterations 3 --threads 2 --out " + refined);
  ASSERT_EQ(from_estimate.code, 0) << from_estimate.err;
  const auto k = nlohmann::json::parse(readFile(refined + "/refine.json"));
  // 10 segments spread over the data, with gaps: independent starts, Schur elimination.
  EXPECT_EQ(k["settings"]["linear_solver"], "SPARSE_SCHUR");
  EXPECT_EQ(k["settings"]["chained_segments"], 0);
  EXPECT_EQ(k["settings"]["continuity_weight"], 10.0);
  EXPECT_TRUE(k.contains("initial_states"));
  // Not a start file: a data error naming the file.
  const Result bad =
      run("refine --robot puma560 --from " + train + " --data " + train + " --out " + refined);
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(contains(bad.err, train)) << bad.err;
  EXPECT_EQ(run("refine --robot puma560 --from x --data y --max-iterations 0 --out d").code, 2);
  EXPECT_EQ(run("refine --robot puma560 --from x --data y --continuity-weight -1 --out d").code, 2);
}

TEST(Cli, SearchStopsCleanlyOnInterrupt) {
  const std::string train = test::tempPath("int_train.csv"), dir = test::tempPath("interrupted");
  ASSERT_EQ(run("simulate --robot puma560 --duration 3 --out " + train).code, 0);
  // SIGINT after 1.5 s of a 60 s budget: the best so far is written and the exit code is 0.
  const std::string command =
      std::string(DYNID_BIN) + " search --method nlo --robot puma560 --data " + train +
      " --perturb 0.3 --seed 1 --segments 20 --budget-seconds 60 " + "--out " + dir +
      " >/dev/null 2>&1 & pid=$!; sleep 1.5; kill -INT $pid; wait $pid";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const auto j = nlohmann::json::parse(readFile(dir + "/search.json"));
  EXPECT_EQ(j["termination"], "interrupted");
  EXPECT_LT(j["seconds"].get<double>(), 30.0);
  EXPECT_GT(j["evaluations"].get<int>(), 0);
}

TEST(Cli, SearchUsageErrors) {
  EXPECT_EQ(run("search --method sgd --robot puma560 --data x.csv --out d").code, 2);
  EXPECT_EQ(run("search --method ga --robot puma560 --data x.csv --threads -1 --out d").code, 2);
  EXPECT_EQ(
      run("search --method ga --robot puma560 --data x.csv --init puma560 --perturb 0.1 --out d")
          .code,
      2);
  const Result missing = run("search --method ga --robot puma560 --data /nonexistent.csv --out d");
  EXPECT_EQ(missing.code, 1);
  EXPECT_TRUE(contains(missing.err, "/nonexistent.csv")) << missing.err;
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

/// "%.3g", as the reports print every number.
std::string g3(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", x);
  return buffer;
}

TEST(Cli, DemoQuickMeetsTheStudysClaimsAndItsReportsAgreeWithTheJson) {
  const std::string dir = test::tempPath("demo");
  const Result r = run("demo --quick --threads 2 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "nlo_refined")) << r.out;
  EXPECT_TRUE(contains(r.out, dir + "/report.html")) << r.out;
  const auto j = nlohmann::json::parse(readFile(dir + "/summary.json"));
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["kind"], "dynid.demo");
  const std::vector<std::string> keys = {
      "ols", "wls", "pc", "nlo", "ga", "hybrid", "nlo_refined", "ga_refined", "hybrid_refined"};
  for (const std::string& key : keys) {
    ASSERT_TRUE(j["methods"].contains(key)) << key;
    for (const char* field :
         {"gc_error_initial", "gc_error_train", "gc_error_test", "torque_rms_test", "param_error",
          "base_param_error", "evaluations", "seconds"})
      EXPECT_TRUE(j["methods"][key][field].is_number()) << key << "." << field;
  }
  const auto& m = j["methods"];
  // Noise-free data: least squares recovers the base parameters to round-off (1e-12 measured).
  EXPECT_LT(m["ols"]["base_param_error"].get<double>(), 1e-6);
  // The searches cut the training GC error at least 10x (about 50x measured in 2 s searches).
  for (const char* key : {"nlo", "ga"})
    EXPECT_GE(m[key]["gc_error_initial"].get<double>(),
              10.0 * m[key]["gc_error_train"].get<double>())
        << key;
  // Refinement reaches the base parameters (1e-12 measured) but not the unidentifiable 7-parameter
  // set: its error stays visibly above zero.
  for (const char* key : {"nlo_refined", "ga_refined", "hybrid_refined"}) {
    EXPECT_LT(m[key]["base_param_error"].get<double>(), 1e-4) << key;
    EXPECT_GT(m[key]["param_error"].get<double>(), 1e-3) << key;
  }
  // The reports carry the same numbers (three significant digits) in every row.
  const std::string markdown = readFile(dir + "/report.md");
  const std::string html = readFile(dir + "/report.html");
  for (const std::string& key : keys) {
    const auto& row = m[key];
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on "| " + key.
    std::string md_row = "| ", html_row = "<tr><td>";
    md_row += key;
    md_row += " |";
    html_row += key;
    html_row += "</td>";
    for (const char* field : {"gc_error_initial", "gc_error_train", "gc_error_test",
                              "torque_rms_test", "param_error", "base_param_error"}) {
      const std::string value = g3(row[field].get<double>());
      md_row += ' ';
      md_row += value;
      md_row += " |";
      html_row += "<td>";
      html_row += value;
      html_row += "</td>";
    }
    EXPECT_TRUE(contains(markdown, md_row)) << md_row;
    EXPECT_TRUE(contains(html, html_row)) << html_row;
  }
  // Self-contained: figures inline, nothing to fetch (SVG's xmlns URIs are names, not fetched).
  EXPECT_FALSE(contains(html, "src=") || contains(html, "<link") || contains(html, "url(") ||
               contains(html, "@import"));
  std::size_t figures = 0;
  for (std::size_t at = html.find("<figure"); at != std::string::npos;
       at = html.find("<figure", at + 1))
    ++figures;
  EXPECT_GE(figures, 7u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/gc_error_iterations.svg"));
  EXPECT_TRUE(contains(markdown, "![Figure 1](gc_error_iterations.svg)"));
  // The GC error is blind to the regressor's null space and to nothing more: 24 of 60 directions,
  // principal angles at round-off (4e-6 degrees measured).
  EXPECT_EQ(j["null_spaces"]["regressor_null"], 24);
  EXPECT_EQ(j["null_spaces"]["gc_near_null"], 24);
  EXPECT_LT(j["null_spaces"]["principal_angles_deg"].back().get<double>(), 1e-3);
  EXPECT_EQ(j["identifiability"]["ols_relative_std_dev_percent"].size(), 36u);
  // The near-truth percentile and the correlations in the captions are summary.json's.
  EXPECT_EQ(j["near_truth"]["samples"], 40);
  EXPECT_TRUE(contains(markdown, g3(j["near_truth"]["percentile"].get<double>()) +
                                     " % of the near-truth configurations"));
  for (const auto& search : j["searches"])
    EXPECT_TRUE(contains(markdown, search["method"].get<std::string>() +
                                       " r = " + g3(search["pearson_log"].get<double>())))
        << search["method"];
  EXPECT_EQ(run("demo --threads -1").code, 2);
}

}  // namespace
}  // namespace dynid

namespace dynid {
namespace {

std::string writeManifest(const std::string& name, const std::string& text) {
  const std::string path = test::tempPath(name);
  std::ofstream(path) << text;
  return path;
}

nlohmann::json resultsOf(const std::string& dir) {
  return nlohmann::json::parse(readFile(dir + "/results.json"));
}

TEST(Cli, BatchRunsTheGridResumesShardsAndMerges) {
  const std::string manifest = writeManifest("batch.json", R"({
    "schema_version": 1,
    "grid": {"method": ["ols", "nlo"], "seed": [1, 2]},
    "fixed": {"train_seconds": 2, "test_seconds": 2, "segments": 10,
              "search_seconds": 0, "search_evaluations": 50}})");
  const std::string dir = test::tempPath("batch_all");
  std::filesystem::remove_all(dir);
  const Result all = run("batch " + manifest + " --jobs 2 --out " + dir);
  ASSERT_EQ(all.code, 0) << all.err;
  const auto table = resultsOf(dir);
  ASSERT_EQ(table["rows"].size(), 4u);
  EXPECT_EQ(table["rows"][0]["method"], "ols");
  EXPECT_EQ(table["rows"][3]["method"], "nlo");
  EXPECT_EQ(table["rows"][3]["seed"], 2);
  EXPECT_EQ(table["rows"][3]["evaluations"], 50);
  const std::string csv = readFile(dir + "/results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);  // header + 4 rows
  // A run that is already done is skipped; one whose result is gone (killed midway) runs again.
  std::filesystem::remove(dir + "/runs/" + table["rows"][1]["run"].get<std::string>() + ".json");
  const Result again = run("batch " + manifest + " --jobs 2 --out " + dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(contains(again.err, "3 already done")) << again.err;
  const auto resumed = resultsOf(dir);
  ASSERT_EQ(resumed["rows"].size(), 4u);
  // The re-run run reproduces its result (deterministic); wall time aside.
  EXPECT_EQ(resumed["rows"][1]["gc_error_train"], table["rows"][1]["gc_error_train"]);
  EXPECT_EQ(resumed["rows"][1]["base_param_error"], table["rows"][1]["base_param_error"]);
  // Shards split the grid; merged, they give the same table (searches are deterministic).
  const std::string s1 = test::tempPath("batch_s1"), s2 = test::tempPath("batch_s2"),
                    merged = test::tempPath("batch_merged");
  for (const std::string& d : {s1, s2, merged}) std::filesystem::remove_all(d);
  ASSERT_EQ(run("batch " + manifest + " --shard 1/2 --out " + s1).code, 0);
  ASSERT_EQ(run("batch " + manifest + " --shard 2/2 --out " + s2).code, 0);
  EXPECT_EQ(resultsOf(s1)["rows"].size(), 2u);
  ASSERT_EQ(run("batch merge " + s1 + " " + s2 + " --out " + merged).code, 0);
  const auto m = resultsOf(merged);
  ASSERT_EQ(m["rows"].size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(m["rows"][i]["run"], table["rows"][i]["run"]);
    EXPECT_EQ(m["rows"][i]["gc_error_train"], table["rows"][i]["gc_error_train"]);
  }
  // Bad input: a data error naming the file and the field, or a usage error.
  const std::string bad = writeManifest("batch_bad.json", R"({"schema_version": 1,
    "grid": {"method": ["ols", "bogus"]}})");
  const Result b = run("batch " + bad + " --out " + dir);
  EXPECT_EQ(b.code, 1);
  EXPECT_TRUE(contains(b.err, bad) && contains(b.err, "grid.method[1]")) << b.err;
  const std::string unknown = writeManifest("batch_unknown.json", R"({"schema_version": 1,
    "fixed": {"method": "ols", "speed": 3}})");
  EXPECT_TRUE(contains(run("batch " + unknown + " --out " + dir).err, "fixed.speed"));
  // A value out of range: refused before any run starts, naming the run and the field, and
  // nothing written.
  const std::string negative = writeManifest("batch_negative.json", R"({"schema_version": 1,
    "grid": {"method": ["ols"], "train_seconds": [2, -1]}})");
  const std::string untouched = test::tempPath("batch_untouched");
  const Result n = run("batch " + negative + " --out " + untouched);
  EXPECT_EQ(n.code, 1);
  EXPECT_TRUE(contains(n.err, "run 1") && contains(n.err, "train_seconds must be > 0")) << n.err;
  EXPECT_FALSE(std::filesystem::exists(untouched));
  EXPECT_EQ(run("batch " + manifest + " --jobs 0 --out " + dir).code, 2);
  EXPECT_EQ(run("batch " + manifest + " --shard 3/2 --out " + dir).code, 2);
}

TEST(Cli, ExampleManifestsRunInQuickMode) {
  for (const char* name : {"paper_searches", "noise_study", "horizon_study"}) {
    const std::string dir = test::tempPath(std::string("example_") + name);
    std::filesystem::remove_all(dir);
    const Result r = run(std::string("batch ") + DYNID_EXAMPLES + "/" + name +
                         ".json --quick --jobs 2 --out " + dir);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    const auto table = resultsOf(dir);
    EXPECT_EQ(table["runs_done"], table["runs_total"]) << name;
    EXPECT_TRUE(table["missing"].empty()) << name;
  }
}

}  // namespace
}  // namespace dynid
