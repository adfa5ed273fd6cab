#include "analysis/run_json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

SearchState sampleState() {
  SearchState s;
  s.method = "hybrid";
  s.stage = "ga";
  s.iteration = 4;
  std::ostringstream rng;
  rng << std::mt19937_64(12345);  // a real generator state: a corrupt one is refused on reading
  s.rng = rng.str();
  s.best_x = Eigen::VectorXd::LinSpaced(5, -1.0, 3.0);
  s.best_gc = 0.125;
  s.initial_gc = std::nan("");  // written as null, read back as NaN
  s.population = {Eigen::VectorXd::Ones(5), Eigen::VectorXd::Zero(5)};
  s.population_gc = {0.5, 0.25};
  s.evaluations = 42;
  s.seconds = 1.5;
  s.history.push_back({"ga", 1, 0.5, 0.1, std::nan(""), 10, 0.2});
  return s;
}

TEST(RunJson, CheckpointRoundTripsEveryField) {
  const SearchState s = sampleState();
  const nlohmann::json settings = {{"form", "paper"}, {"budget_seconds", 3.0}, {"seed", 1}};
  const nlohmann::json doc = checkpointJson(s, settings);
  // The fingerprint drops the budgets: a run can be resumed with a larger one.
  EXPECT_FALSE(doc["settings"].contains("budget_seconds"));
  EXPECT_EQ(doc["settings"]["form"], "paper");
  const SearchState back = checkpointFrom(nlohmann::json::parse(doc.dump()), "ck.json");
  EXPECT_EQ(back.method, s.method);
  EXPECT_EQ(back.stage, s.stage);
  EXPECT_EQ(back.iteration, s.iteration);
  EXPECT_EQ(back.rng, s.rng);
  EXPECT_EQ(back.best_x, s.best_x);
  EXPECT_EQ(back.best_gc, s.best_gc);
  EXPECT_TRUE(std::isnan(back.initial_gc));
  ASSERT_EQ(back.population.size(), 2u);
  EXPECT_EQ(back.population[1], s.population[1]);
  EXPECT_EQ(back.population_gc, s.population_gc);
  EXPECT_EQ(back.evaluations, s.evaluations);
  ASSERT_EQ(back.history.size(), 1u);
  EXPECT_EQ(back.history[0].best_parameter_error, 0.1);
  EXPECT_TRUE(std::isnan(back.history[0].min_parameter_error));
}

TEST(RunJson, ACorruptCheckpointIsAParseErrorNamingTheFile) {
  nlohmann::json doc = checkpointJson(sampleState(), nlohmann::json::object());
  doc.erase("rng");
  try {
    checkpointFrom(doc, "run/ck.json");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "run/ck.json");
  }
}

TEST(RunJson, ARefineStartReadsBackTheSearchsSpaceAndEstimate) {
  // A search.json's settings and estimates, as searchRun and reports/ write them.
  const Model robot = makePuma560(false);
  const Model guess = perturbedModel(robot, 0.2, 3);
  SpaceOptions space_options;
  space_options.fixed = {"m1", "cz2"};
  space_options.total_mass_constraint = true;
  space_options.total_mass = totalMass(guess);
  const ParameterSpace space(guess, space_options);
  SearchSettingsRecord record{space_options, space.freeNames(), {}, 7, {}, {}, {}, "train.csv"};
  record.segments.num_segments = 12;
  record.segments.step = 1e-3;
  const nlohmann::json doc = {{"schema_version", 1},
                              {"settings", searchSettingsJson(record)},
                              {"estimate", estimateJson(space, space.initial() * 1.01)},
                              {"initial_estimate", estimateJson(space, space.initial())}};
  const RefineStart start = refineStartFrom(doc, "search.json", robot, {}, {});
  EXPECT_EQ(start.kind, "search");
  EXPECT_EQ(start.segments.num_segments, 12);
  EXPECT_EQ(start.segments.seed, 7u);
  EXPECT_TRUE(start.space.total_mass_constraint);
  const ParameterSpace rebuilt(start.initial, start.space);
  EXPECT_EQ(rebuilt.freeNames(), space.freeNames());
  // The estimate comes back through its standard parameters (round-off of the paper form).
  const Eigen::VectorXd x = rebuilt.freeOf(rebuilt.fullVector(start.estimate));
  EXPECT_LT((x - space.initial() * 1.01).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RunJson, ARefineStartNamesTheMissingField) {
  const Model robot = makePuma560(false);
  nlohmann::json doc = {{"schema_version", 1}, {"standard_estimate", {{"values", {{"m1", 1.0}}}}}};
  try {
    refineStartFrom(doc, "est.json", robot, {}, {});
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "est.json");
    EXPECT_EQ(e.element(), "standard_estimate.values.mx1");
  }
  EXPECT_THROW(refineStartFrom(nlohmann::json::object(), "x.json", robot, {}, {}), ParseError);
  EXPECT_THROW(parseJson("{not json", "x.json"), ParseError);
}

/// The element of the ParseError that reading `doc` as an estimate.json for the PUMA throws.
std::string estimateFault(const nlohmann::json& doc) {
  const std::vector<std::string> names =
      standardParameterNames(makePuma560(false).parameterLayout());
  try {
    standardVectorFrom(estimateRecordFrom(doc, "est.json"), names, "est.json", "puma560");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "est.json");
    return e.element();
  }
  return "";
}

TEST(RunJson, AnEstimateIsReadStrictly) {
  const Model robot = makePuma560(false);
  const std::vector<std::string> names = standardParameterNames(robot.parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (std::size_t k = 0; k < names.size(); ++k) values[names[k]] = 0.5 + static_cast<double>(k);
  const nlohmann::json good = {{"schema_version", 1},
                               {"robot_spec", "puma560"},
                               {"drive_terms", nlohmann::json::array()},
                               {"standard_estimate", {{"note", "n"}, {"values", values}}}};
  const Eigen::VectorXd theta =
      standardVectorFrom(estimateRecordFrom(good, "est.json"), names, "est.json", "puma560");
  EXPECT_EQ(theta[3], 3.5);  // in the layout's order, whatever the document's key order
  EXPECT_EQ(estimateFault(good), "");
  nlohmann::json bad = good;
  bad["schema_version"] = 99;
  EXPECT_EQ(estimateFault(bad), "schema_version");
  bad = good;
  bad["standard_estimat"] = nlohmann::json::object();
  EXPECT_EQ(estimateFault(bad), "standard_estimat");
  bad = good;
  bad["standard_estimate"]["values"]["m3"] = 1e300;  // finite, but no robot's parameter
  EXPECT_EQ(estimateFault(bad), "standard_estimate.values.m3");
  bad = good;
  bad["standard_estimate"]["values"].erase("Ixx3");
  EXPECT_EQ(estimateFault(bad), "standard_estimate.values.Ixx3");
  bad = good;
  bad["standard_estimate"]["values"]["Ia3"] = 0.1;  // a drive parameter this robot does not have
  EXPECT_EQ(estimateFault(bad), "standard_estimate.values.Ia3");
  bad = good;
  bad["drive_terms"] = {"fv", 3};
  EXPECT_EQ(estimateFault(bad), "drive_terms[1]");
}

}  // namespace
}  // namespace dynid
