#include "analysis/studies/log_study.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>

#include "tests/common/identification.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/study_rows.hpp"

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "data/dataset_csv.hpp"

namespace dynid {
namespace {

struct Files {
  std::string train, test;
};

/// Noise-free PUMA data: 3 s of training data split into two runs by a 1 s gap (as `dynid
/// prepare` writes a log with a gap), and 2 s held out on another motion.
Files writeData() {
  const Model model = makePuma560(false);
  Trajectory train = test::pumaTrajectory(model, 3.0, 0.0, 1);
  for (int k = train.numSamples() / 2; k < train.numSamples(); ++k) train.time[k] += 1.0;
  Files f{test::tempPath("study_train.csv"), test::tempPath("study_test.csv")};
  writeDatasetCsv(f.train, train);
  writeDatasetCsv(f.test, test::pumaTrajectory(model, 2.0, 0.0, 2, 1.3));
  return f;
}

LogStudyRequest request(const Files& f, int threads) {
  LogStudyRequest r;
  r.robot = makePuma560(false);
  r.robot_spec = "puma560";
  r.data_file = f.train;
  r.validate_file = f.test;
  r.methods = {Method::kOls, Method::kPc, Method::kNlo, Method::kNloRefined};
  r.segments.num_segments = 20;
  r.search_seconds = 0.0;
  r.search_evaluations = 150;  // deterministic for a seed, whatever the machine
  r.refine_iterations = 3;
  r.refine_seconds = 0.0;
  r.threads = threads;
  return r;
}

TEST(LogStudy, MeasuresEveryMethodOnBothDatasets) {
  const Files f = writeData();
  const LogStudyOutcome o = logStudyRun(request(f, 1));
  std::vector<std::string> keys;
  for (const LogStudyRow& r : o.rows) keys.push_back(r.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"model", "start", "ols", "pc", "nlo", "nlo_refined"}));
  EXPECT_EQ(o.train_segments, 20);
  EXPECT_EQ(o.num_base, 36);
  const LogStudyRow& model = o.rows[0];
  const LogStudyRow& ols = o.rows[2];
  // Noise-free data from the model itself: the model and OLS reproduce the torques (round-off of
  // the simulation and the least squares) and the motion (the recorded integrator and step).
  EXPECT_LT(model.torque_train, 1e-9);
  EXPECT_LT(model.gc_test, 1e-12);
  EXPECT_LT(ols.torque_test, 1e-6);
  EXPECT_LT(ols.gc_train, 1e-6);
  EXPECT_TRUE(model.consistent == false);  // the PUMA's link 1 is massless with a rank-1 inertia
  // The searches start from pc and are measured like the rest; budgets as asked.
  EXPECT_EQ(o.rows[4].evaluations, 150);
  for (const LogStudyRow& r : o.rows) {
    EXPECT_TRUE(std::isfinite(r.torque_train) && std::isfinite(r.gc_test)) << r.key;
    EXPECT_GE(r.gc_train, 0.0) << r.key;
  }
  // The refinement starts from the NLO result and does not end worse on the training data (up to
  // the round-off of a GC error at the truth, ~1e-15, which noise-free data start from).
  EXPECT_LE(o.rows[5].gc_train, o.rows[4].gc_train * (1.0 + 1e-9) + 1e-12);
}

TEST(LogStudy, TheSameSeedGivesTheSameTableWhateverTheThreads) {
  const Files f = writeData();
  const LogStudyOutcome one = logStudyRun(request(f, 1));
  const LogStudyOutcome two = logStudyRun(request(f, 2));
  ASSERT_EQ(one.rows.size(), two.rows.size());
  for (std::size_t k = 0; k < one.rows.size(); ++k) {
    EXPECT_EQ(one.rows[k].gc_train, two.rows[k].gc_train) << one.rows[k].key;
    EXPECT_EQ(one.rows[k].torque_test, two.rows[k].torque_test) << one.rows[k].key;
  }
}

TEST(LogStudy, StopsCleanlyAndRefusesBadSettings) {
  const Files f = writeData();
  LogStudyRequest stopped = request(f, 1);
  std::atomic<bool> stop{true};
  stopped.control.stop = &stop;
  const LogStudyOutcome o = logStudyRun(stopped);
  EXPECT_TRUE(o.interrupted);
  EXPECT_EQ(o.rows.front().key, "model");  // measured before any method
  LogStudyRequest no_test = request(f, 1);
  no_test.validate_file.clear();
  EXPECT_THROW(logStudyRun(no_test), InputError);
  LogStudyRequest no_budget = request(f, 1);
  no_budget.search_evaluations = 0;
  EXPECT_THROW(logStudyRun(no_budget), InputError);
  LogStudyRequest long_horizon = request(f, 1);
  long_horizon.segments.horizon = 5.0;  // longer than either run
  EXPECT_THROW(logStudyRun(long_horizon), InputError);
}

constexpr auto row = test::studyRow;

TEST(LogStudyVerdict, RecommendsOnlyConsistentEstimatesWithFiniteErrors) {
  // Every branch: the overall bests inconsistent (ols, nlo), the recommendations consistent.
  std::vector<LogStudyRow> rows = {
      row("model", 0.04, 50.0, true), row("start", 0.011, 80.0, true),
      row("ols", 0.010, 6e6, false),  row("pc", 0.011, 80.0, true),
      row("nlo", 0.02, 30.0, false),  row("combined", 0.0115, 40.0, true)};
  StudyVerdict v = studyVerdict(rows);
  EXPECT_EQ(v.best_torque, "ols");
  EXPECT_EQ(v.best_gc, "nlo");
  EXPECT_EQ(v.control, "pc");
  EXPECT_EQ(v.simulation, "combined");
  EXPECT_FALSE(v.oneForBoth());
  // The input model is a candidate like any consistent row.
  rows[0].gc_test = 35.0;
  EXPECT_EQ(studyVerdict(rows).simulation, "model");
  // One consistent row best at both.
  rows[0].gc_test = 50.0;
  rows[5].torque_test = 0.0105;
  v = studyVerdict(rows);
  EXPECT_TRUE(v.oneForBoth());
  EXPECT_EQ(v.simulation, "combined");
  // A non-finite held-out error never wins; "start" stands in for pc only when pc has no row.
  rows[5].gc_test = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(studyVerdict(rows).simulation, "model");
  const std::vector<LogStudyRow> searches_only = {row("start", 0.011, 80.0, true),
                                                  row("nlo", 0.02, 30.0, false)};
  v = studyVerdict(searches_only);
  EXPECT_EQ(v.simulation, "start");
  EXPECT_EQ(v.best_gc, "nlo");
  // No consistent row: no recommendation at all.
  v = studyVerdict({row("ols", 0.01, 1.0, false)});
  EXPECT_TRUE(v.simulation.empty() && v.control.empty());
  EXPECT_EQ(v.best_torque, "ols");
}

TEST(LogStudyChoice, TheLeastGcErrorWithinTheToleranceOfTheBestConsistentTorqueFit) {
  using test::studyRow;
  LogStudyOutcome o;
  o.rows = {studyRow("model", 0.095, 400.0, true), studyRow("start", 0.0269, 59300.0, true),
            studyRow("ols", 0.020, 1e6, false), studyRow("pc", 0.0269, 59300.0, true),
            studyRow("combined", 0.0269, 2970.0, true)};
  o.front = {{0.1, studyRow("front", 0.0270, 1500.0, true)},
             {1.0, studyRow("front", 0.0285, 900.0, true)},
             {10.0, studyRow("front", 0.040, 500.0, true)}};
  // ols fits best but is not consistent: the bound is 5 % above pc's (the first of the ties).
  StudyChoice c = studyChoice(o, 0.05);
  EXPECT_EQ(c.best_torque, "pc");
  EXPECT_NEAR(c.torque_bound, 1.05 * 0.0269, 1e-15);
  EXPECT_EQ(c.key, "front");
  EXPECT_EQ(c.front_index, 0);
  c = studyChoice(o, 0.1);  // the point at w = 1 (2.85 % <= 2.959 %) predicts better
  EXPECT_EQ(c.front_index, 1);
  // Wide enough to take the input model (9.5 %), which predicts the motion best: it is chosen,
  // as any other estimate would be.
  c = studyChoice(o, 4.0);
  EXPECT_EQ(c.key, "model");
  EXPECT_EQ(c.front_index, -1);
  // Without a front, the rows alone; none consistent: nothing chosen.
  o.front.clear();
  EXPECT_EQ(studyChoice(o, 0.05).key, "combined");
  for (LogStudyRow& r : o.rows) r.consistent = false;
  EXPECT_TRUE(studyChoice(o, 0.05).key.empty());
}

TEST(LogStudy, CombinedTradesLittleTorqueFitForTheMotion) {
  Files f{test::tempPath("study_noisy_train.csv"), test::tempPath("study_noisy_test.csv")};
  const Model model = makePuma560(false);
  writeDatasetCsv(f.train, test::pumaTrajectory(model, 3.0, 0.5, 1));
  writeDatasetCsv(f.test, test::pumaTrajectory(model, 2.0, 0.5, 2, 1.3));
  LogStudyRequest r = request(f, 1);
  r.robot = perturbedModel(model, 0.2, 4);  // a prior off the truth, as a CAD model is
  r.methods = {Method::kPc, Method::kCombined};
  r.refine_iterations = 20;
  const LogStudyOutcome o = logStudyRun(r);
  ASSERT_EQ(o.rows.size(), 3u);  // model, pc, combined: no search, no "start"
  const LogStudyRow& pc = o.rows[1];
  const LogStudyRow& combined = o.rows[2];
  EXPECT_EQ(combined.key, "combined");
  EXPECT_TRUE(combined.consistent);
  EXPECT_FALSE(combined.note.empty());
  // It starts at pc and keeps only steps that lower its cost: on this noisy log (pc's GC error
  // near its noise floor) it stays close to pc, its torque fit within 2 % of pc's.
  EXPECT_LE(combined.gc_train, pc.gc_train * (1.0 + 1e-9));
  EXPECT_LT(combined.torque_train, 1.02 * pc.torque_train);
  EXPECT_TRUE(o.front.empty());  // none asked for
  // Weights that are not a sweep: refused before any work, by field name.
  r.front_weights = {1.0, 0.5};
  try {
    logStudyRun(r);
    FAIL() << "a front of decreasing weights was swept";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("`front_weights`"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynid
