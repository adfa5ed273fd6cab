#include "analysis/records/estimate_record.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "analysis/records/search_record.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/perturb.hpp"
#include "data/model_json.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

TEST(EstimateRecord, ARefineStartReadsBackTheSearchsSpaceAndEstimate) {
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

TEST(EstimateRecord, ARefineStartNamesTheMissingField) {
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

TEST(EstimateRecord, AnEstimateIsReadStrictly) {
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

TEST(EstimateRecord, VersionTwoCarriesRestVelocitiesAndVersionOneIsStillRead) {
  const std::vector<std::string> names =
      standardParameterNames(makePuma560(false).parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (const std::string& name : names) values[name] = 1.0;
  nlohmann::json doc = {{"schema_version", 1},
                        {"standard_estimate", {{"note", "n"}, {"values", values}}}};
  EXPECT_TRUE(estimateRecordFrom(doc, "est.json").rest_velocities.empty());  // version 1: none
  doc["rest_velocity"] = {{"velocity", {1e-3, 2e-3, 0, 0, 0, 0}}, {"source", {"noise"}}};
  doc["schema_version"] = kEstimateDocument.schema_version;
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").rest_velocities[1], 2e-3);
  doc["rest_velocity"]["velocity"][2] = -1.0;
  EXPECT_EQ(estimateFault(doc), "rest_velocity.velocity[2]");
  doc["rest_velocity"] = 3;
  EXPECT_EQ(estimateFault(doc), "rest_velocity");
}

TEST(EstimateRecord, VersionThreeNamesItsCovariancePolicyAndEveryEarlierVersionIsRead) {
  const std::vector<std::string> names =
      standardParameterNames(makePuma560(false).parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (const std::string& name : names) values[name] = 1.0;
  const nlohmann::json covariance = {{"note", "n"}, {"columns", {"m1"}}, {"matrix", {{0.25}}}};
  nlohmann::json doc = {{"schema_version", 2},
                        {"standard_estimate", {{"note", "n"}, {"values", values}}},
                        {"base_covariance", covariance}};
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").covariance_policy, "white");  // before version 3
  doc["schema_version"] = 3;
  doc["base_covariance"]["policy"] = {{"name", "hac"}, {"batch", 64}, {"inflation", 3.0}};
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").covariance_policy, "hac");
  doc["base_covariance"]["policy"]["name"] = "newey-west";
  EXPECT_EQ(estimateFault(doc), "base_covariance.policy.name");
  doc["base_covariance"]["policy"] = {{"name", "white"}, {"colour", "blue"}};
  EXPECT_EQ(estimateFault(doc), "base_covariance.policy.colour");
  doc["schema_version"] = 0;  // no version 0 was ever written
  EXPECT_EQ(estimateFault(doc), "schema_version");
}

TEST(EstimateRecord, VersionFourCarriesItsFitRows) {
  const std::vector<std::string> names =
      standardParameterNames(makePuma560(false).parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (const std::string& name : names) values[name] = 1.0;
  nlohmann::json doc = {{"schema_version", 4},
                        {"standard_estimate", {{"note", "n"}, {"values", values}}},
                        {"fit_rows", {{"rows", {10, 9, 10, 10, 8, 10}}, {"samples", 10}}}};
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").standard.size(), names.size());
  doc["schema_version"] = 3;  // an earlier version with a key it did not have: still read
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").standard.size(), names.size());
  doc["schema_version"] = kEstimateDocument.schema_version + 1;  // a later version: refused
  EXPECT_EQ(estimateFault(doc), "schema_version");
}

TEST(EstimateRecord, VersionFiveEmbedsItsRobotAndWhereItCameFrom) {
  const Model puma = makePuma560(false);
  const std::vector<std::string> names = standardParameterNames(puma.parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (const std::string& name : names) values[name] = 1.0;
  const std::string sha(64, 'a');
  nlohmann::json doc = {
      {"schema_version", 5},
      {"standard_estimate", {{"note", "n"}, {"values", values}}},
      {"model", nlohmann::json::parse(modelToJson(puma))},
      {"model_source", {{"spec", "/lab/arm.urdf"}, {"file", "arm.urdf"}, {"sha256", sha}}}};
  const EstimateRecord record = estimateRecordFrom(doc, "est.json");
  EXPECT_EQ(record.model["name"], puma.name);
  EXPECT_EQ(record.model_file, "arm.urdf");
  EXPECT_EQ(record.model_sha256, sha);
  doc["model_source"] = {{"spec", "puma560"}, {"file", nullptr}, {"sha256", nullptr}};  // built in
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").model_sha256, "");
  doc["model_source"]["sha256"] = "ABC";
  EXPECT_EQ(estimateFault(doc), "model_source.sha256");
  doc.erase("model_source");  // the model without where it came from
  EXPECT_EQ(estimateFault(doc), "model_source");
  doc["model"] = 3;
  EXPECT_EQ(estimateFault(doc), "model");
}

// Version 6 adds what made it (records/provenance.hpp): read when present, and checked.
TEST(EstimateRecord, VersionSixRecordsWhatMadeIt) {
  EXPECT_EQ(kEstimateDocument.schema_version, 8);  // 8: front; 7 read as it is
  const std::vector<std::string> names =
      standardParameterNames(makePuma560(false).parameterLayout());
  nlohmann::json values = nlohmann::json::object();
  for (const std::string& name : names) values[name] = 1.0;
  RunProvenance run;
  run.interface = "cli";
  run.command = {"dynid", "identify"};
  nlohmann::json doc = {{"schema_version", 6},
                        {"standard_estimate", {{"note", "n"}, {"values", values}}},
                        {"provenance", provenanceJson(run, "dynid.estimate")}};
  EXPECT_EQ(estimateRecordFrom(doc, "est.json").standard.size(), names.size());
  doc["provenance"]["inputs"] = "train.csv";
  EXPECT_EQ(estimateFault(doc), "provenance.inputs");
}

}  // namespace
}  // namespace dynid
