// The identification report (report.md, report.html) of an identify run on simulated PUMA data.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "core/format.hpp"
#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/text.hpp"

#include "analysis/records/estimate_record.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "reports/identification_report.hpp"
#include "reports/plots.hpp"
#include "reports/prediction_report.hpp"

namespace dynid {
namespace {

using test::contains;

struct Fixture {
  std::string dir, train, validate;
};

/// train.csv and validate.csv of the PUMA with drives, beside a prepare.json when `prepared`
/// (with `source`, its "source" member: how the torques were made).
Fixture writeData(bool prepared, const std::string& source = "") {
  Fixture f;
  f.dir = test::tempPath(prepared ? "prepared" : "plain");
  std::filesystem::create_directories(f.dir);
  const Model model = makePuma560(true);
  f.train = f.dir + "/train.csv";
  f.validate = f.dir + "/validate.csv";
  writeDatasetCsv(f.train, test::pumaTrajectory(model, 3.0, 0.05, 1));
  writeDatasetCsv(f.validate, test::pumaTrajectory(model, 1.0, 0.05, 2, 1.3));
  if (prepared)
    writeFileAtomically(f.dir + "/prepare.json", R"({"kind": "dynid.prepare",
      "raw": {"samples": 4321, "median_step": 0.001, "min_step": 0.0007, "max_step": 0.0088,
              "repeated_stamps_dropped": 3},
      "gaps": [], "max_gap": 0.02, "runs": [{}], "dropped_runs": [], "resampled_rate": 1000,
      "filter": {"kind": "Butterworth", "order": 4, "cutoff_hz": 7.5, "applied_to": "q, dq, tau"},
      "dq": "logged", "ddq": "central differences", "trimmed_each_end": 0.4, "decimate": 1,
      "tau_noise_rms": [0.1, 0.2])" + (source.empty() ? "" : ", \"source\": " + source) +
                                                     "}");
  return f;
}

IdentifyRequest request(const Fixture& f, Method method) {
  IdentifyRequest r;
  r.model = makePuma560(true);
  r.method = method;
  r.data_file = f.train;
  r.validate_file = f.validate;
  r.robot_spec = "puma560";
  return r;
}

TEST(EstimateReport, ShowsTheFitTheBaseParametersTheVerdictsAndTheUnknowns) {
  const Fixture f = writeData(true);
  IdentifyRequest r = request(f, Method::kOls);
  // m1 never acts on the torques: the model's (the lift's) negative m1 makes link 1 inconsistent.
  Eigen::VectorXd theta = r.model.standardParameters();
  theta[r.model.parameterLayout().linkIndex(0, 0)] = -1.0;
  r.model.setStandardParameters(theta);
  const IdentifyOutcome o = identifyRun(r);
  ASSERT_TRUE(o.preparation.present);
  ASSERT_TRUE(o.preparation.record.has_value());
  std::vector<std::string> missing;
  const Document doc = identificationDocument(r.model, o, &missing);
  const std::string md = doc.markdown();
  // The verdict first: what, how well (training and held out), what not, the torque source (a
  // prepared log without currents: as recorded), what next (--method pc for the inconsistent
  // link).
  EXPECT_EQ(md.find("> **Verdict**"), md.find("\n") + 2) << md;
  EXPECT_TRUE(contains(md, "> - **How well:** relative torque error ")) << md;
  EXPECT_TRUE(contains(md, " held out (")) << md;
  EXPECT_TRUE(contains(md, "> - **Torque source:** the log's torque columns as recorded")) << md;
  EXPECT_TRUE(contains(md, "--method pc for an estimate every link of which is a physical body"))
      << md;
  // The torque table: every joint, training and held-out columns.
  EXPECT_TRUE(contains(md,
                       "| joint | measured RMS [N m] | residual RMS [N m] | relative error | "
                       "held-out residual RMS [N m] | held-out relative error |"));
  for (int j = 1; j <= 6; ++j) EXPECT_TRUE(contains(md, "\n| " + std::to_string(j) + " | ")) << j;
  // The preprocessing record beside train.csv.
  EXPECT_TRUE(contains(md, "## Preprocessing (dynid prepare)"));
  EXPECT_TRUE(contains(md, "4321 raw samples")) << md;
  EXPECT_TRUE(contains(md, "cutoff 7.5 Hz"));
  // Both condition numbers, as the estimate has them.
  EXPECT_TRUE(contains(md, "training base regressor: " +
                               formatNumber(o.result.estimate.condition_number_unscaled, 3, "n/a") +
                               " as it is"))
      << md;
  EXPECT_TRUE(contains(md, ", " + formatNumber(o.result.estimate.condition_number, 3, "n/a") +
                               " with unit columns"));
  // The base-parameter table: every base parameter with its excitation.
  EXPECT_TRUE(contains(md, "| # | base parameter | combination | estimate | %σ | excitation |"));
  EXPECT_TRUE(contains(md, "\n| 1 | Iyy1R | Iyy1 + Ia1 ")) << md;
  // Link 1 violates the mass condition; the PUMA's other links are consistent.
  EXPECT_TRUE(contains(md, "| link1 | violates: mass >= 0")) << md;
  EXPECT_TRUE(contains(md, "| link2 | consistent |"));
  // What the data cannot determine: m1 never acts.
  EXPECT_TRUE(contains(md, "never act on the torques, whatever the motion: m1, "));
  // gnuplot (installed by scripts/install-deps.sh) draws the four figures.
  EXPECT_TRUE(missing.empty());
  std::vector<std::string> names;
  for (const Figure& fig : doc.figures()) names.push_back(fig.name);
  EXPECT_EQ(names, (std::vector<std::string>{"torques_train", "torques_validate", "residuals",
                                             "residual_histogram"}));
  const std::string html = doc.html();
  EXPECT_TRUE(contains(html, "<figure id=\"torques_validate\">"));
  for (int j = 1; j <= 6; ++j)  // a panel per joint
    EXPECT_TRUE(contains(html, "tau" + std::to_string(j) + " [N m]")) << j;
}

TEST(EstimateReport, WritesEveryFileAndPcIsConsistentOnEveryLink) {
  const Fixture f = writeData(false);
  const IdentifyRequest r = request(f, Method::kPc);
  const IdentifyOutcome o = identifyRun(r);
  EXPECT_FALSE(o.preparation.present);  // no prepare.json beside the data
  EXPECT_TRUE(o.violations.empty());
  const std::string out = test::tempPath("report");
  const std::string summary = writeIdentification(out, r.model, o);
  EXPECT_TRUE(contains(summary, "report.html"));
  for (const char* name : {"estimate.json", "report.md", "report.html", "torques_train.svg",
                           "torques_validate.svg", "residuals.svg", "residual_histogram.svg"})
    EXPECT_TRUE(std::filesystem::is_regular_file(out + "/" + name)) << name;
  const std::string md = readFile(out + "/report.md");
  EXPECT_FALSE(contains(md, "Preprocessing"));
  EXPECT_FALSE(contains(md, "violates"));
  EXPECT_TRUE(contains(md, "The physically consistent solver (pc) stopped after"));
  // Without gnuplot: the report and a warning, no figures.
  ::setenv("DYNID_GNUPLOT", "/nonexistent/gnuplot", 1);
  const std::string bare = test::tempPath("bare");
  const std::string warned = writeIdentification(bare, r.model, o);
  ::unsetenv("DYNID_GNUPLOT");
  EXPECT_TRUE(contains(warned, "warning: gnuplot did not run")) << warned;
  EXPECT_TRUE(std::filesystem::is_regular_file(bare + "/report.html"));
  EXPECT_FALSE(std::filesystem::exists(bare + "/residuals.svg"));
}

TEST(EstimateReport, NextSaysWhatWouldDetermineEachPoorlyDeterminedParameter) {
  const Fixture f = writeData(false);
  IdentifyOutcome o = identifyRun(request(f, Method::kOls));
  // Six constructed cases over the first base parameters, the rest well determined: 5 % (fine),
  // 15 % (4 times the samples bring it to 7.5 %), 80 % (|estimate| < 2 sigma), 30 % and nearly a
  // combination of the others, 30 % and 40 % on their own (more excitation).
  BaseEstimate& e = o.result.estimate;
  const int b = static_cast<int>(e.beta.size());
  ASSERT_GE(b, 6);
  e.beta.setOnes();
  e.independence = Eigen::VectorXd::Ones(b);
  const double percent[] = {5.0, 15.0, 80.0, 30.0, 30.0, 40.0};
  e.relative_std_dev_percent = Eigen::VectorXd::Constant(b, 1.0);
  for (int j = 0; j < 6; ++j) e.relative_std_dev_percent[j] = percent[j];
  e.std_dev = e.relative_std_dev_percent / 100.0;  // beta = 1
  e.independence[3] = 0.05;
  const std::string md =
      identificationDocument(request(f, Method::kOls).model, o, nullptr).markdown();
  EXPECT_TRUE(contains(md,
                       "of the 5 poorly determined base parameters, 1 would come within 10 % "
                       "with 4 times the samples of this motion"))
      << md;
  EXPECT_TRUE(contains(md, ", 1 are not significantly different from zero (|estimate| < 2σ")) << md;
  EXPECT_TRUE(contains(md,
                       " and 3 (1 nearly combinations of others) need more excitation: a "
                       "motion designed by dynid excite, or a longer log"))
      << md;
  // All well determined: no such advice.
  e.relative_std_dev_percent.setConstant(1.0);
  e.std_dev.setConstant(0.01);
  const std::string fine =
      identificationDocument(request(f, Method::kOls).model, o, nullptr).markdown();
  EXPECT_FALSE(contains(fine, "poorly determined base parameters,")) << fine;
}

// Every estimate.json identify writes reads back as predict, monitor and payload read it: the
// combined method's record (its "combined" block was refused as an unknown key) and a prepared
// log's torque constants (torque_source).
// The friction note: joints whose residual has friction's shape, largest first, and the terms
// the model lacks with the --drive-terms that adds them; none when it has them all.
TEST(EstimateReport, TheFrictionNoteNamesTheJointsAndTheMissingTerms) {
  ReversalResidual r;
  r.samples = 100;
  r.speed.setZero(3);
  r.sample_share.setZero(3);
  r.residual_share.setZero(3);
  r.friction_share = Eigen::Vector3d(0.5, 0.1, 0.9);
  r.friction_flagged = {0, 2};
  const std::string note = reversalNote(parseDriveTerms("fv"), r);
  EXPECT_NE(note.find("explains 90 % of it on joint 3 (joint 1: 50 %)"), std::string::npos) << note;
  EXPECT_NE(note.find("the drive terms lack fc, fo: --drive-terms fv,fc,fo adds them"),
            std::string::npos)
      << note;
  EXPECT_EQ(reversalNote(parseDriveTerms("fv,fc,fo"), r), "");  // nothing flagged at reversals
}

TEST(EstimateReport, EveryMethodsEstimateReadsBack) {
  const Fixture f = writeData(true, R"({"current_to_torque": {
      "torque_constants": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6],
      "gear_ratios": [100, 100, 100, 50, 50, 50]}})");
  for (Method method : {Method::kOls, Method::kWls, Method::kPc, Method::kCombined}) {
    IdentifyRequest r = request(f, method);
    r.combined.max_iterations = 2;  // the record's shape, not the estimate, is under test
    const IdentifyOutcome o = identifyRun(r);
    const nlohmann::json document = estimateJson(r.model, o);
    EXPECT_EQ(document.contains("combined"), method == Method::kCombined);
    EstimateRecord back;
    ASSERT_NO_THROW(back = estimateRecordFrom(document, "estimate.json")) << methodName(method);
    EXPECT_EQ(back.method, methodName(method));
    EXPECT_EQ(back.torque_constants, (std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5, 0.6}));
    EXPECT_EQ(back.gear_ratios, (std::vector<double>{100, 100, 100, 50, 50, 50}));
  }
  // Without currents, no torque source.
  const Fixture plain = writeData(false);
  const IdentifyOutcome o = identifyRun(request(plain, Method::kOls));
  EXPECT_FALSE(estimateJson(makePuma560(true), o).contains("torque_source"));
}

}  // namespace
}  // namespace dynid
