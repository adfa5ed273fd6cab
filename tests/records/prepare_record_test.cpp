#include "analysis/records/prepare_record.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "analysis/records/document.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

/// The fields of a prepare.json that the reader takes, as `dynid prepare` writes them.
nlohmann::json prepared() {
  nlohmann::json doc = documentHeader(kPrepareDocument);
  doc["raw"] = {{"samples", 1000},
                {"repeated_stamps_dropped", 2},
                {"median_step", 0.001},
                {"min_step", 0.0009},
                {"max_step", nullptr}};
  doc["max_gap"] = 0.005;
  doc["gaps"] = nlohmann::json::array({1.5});
  doc["runs"] = nlohmann::json::array({{0.0, 1.5}, {1.6, 3.0}});
  doc["dropped_runs"] = nlohmann::json::array();
  doc["resampled_rate"] = 1000.0;
  doc["filter"] = {{"kind", "Butterworth"},
                   {"order", 4},
                   {"cutoff_hz", 10.0},
                   {"cutoff_choice", "5 x the trajectory band"},
                   {"applied_to", "q, dq, tau"}};
  doc["dq"] = "central differences of the filtered q";
  doc["ddq"] = "central differences of dq";
  doc["trimmed_each_end"] = 0.2;
  doc["decimate"] = 1;
  doc["tau_noise_rms"] = {0.1, nullptr};
  return doc;
}

TEST(PrepareRecord, ReadsWhatAReportRestates) {
  const std::optional<PrepareRecord> r = prepareRecordFrom(prepared());
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->raw_samples, 1000);
  EXPECT_EQ(r->repeated_stamps_dropped, 2);
  EXPECT_TRUE(std::isnan(r->max_step));  // null: not measured
  EXPECT_EQ(r->gaps, 1);
  EXPECT_EQ(r->runs, 2);
  EXPECT_EQ(r->dropped_runs, 0);
  EXPECT_EQ(r->filter_order, 4);
  EXPECT_EQ(r->cutoff_choice.value_or(""), "5 x the trajectory band");
  ASSERT_EQ(r->tau_noise_rms.size(), 2u);
  EXPECT_TRUE(std::isnan(r->tau_noise_rms[1]));
}

TEST(PrepareRecord, AnotherDocumentOrAMissingFieldIsNoRecord) {
  nlohmann::json other = prepared();
  other["kind"] = kEstimateDocument.kind;
  EXPECT_FALSE(prepareRecordFrom(other).has_value());
  nlohmann::json short_of_a_field = prepared();
  short_of_a_field.erase("decimate");
  EXPECT_FALSE(prepareRecordFrom(short_of_a_field).has_value());
  EXPECT_FALSE(prepareRecordFrom(nlohmann::json::array()).has_value());
}

TEST(PrepareRecord, IsFoundBesideAPreparedDatasetOnly) {
  const std::filesystem::path dir = test::tempPath("prepare_record");
  std::filesystem::create_directories(dir);
  const std::string train = (dir / "train.csv").string();
  const auto write = [&](const std::string& text) {
    std::ofstream((dir / "prepare.json").string()) << text;
  };
  EXPECT_FALSE(findPreparation(train).present);  // no prepare.json
  write(prepared().dump());
  const PreparationFound found = findPreparation(train);
  EXPECT_TRUE(found.present);
  ASSERT_TRUE(found.record.has_value());
  EXPECT_EQ(found.record->raw_samples, 1000);
  EXPECT_FALSE(findPreparation((dir / "other.csv").string()).present);  // not prepare's output
  write("{ not json");
  EXPECT_FALSE(findPreparation(train).present);  // unreadable: not the dataset's problem
  nlohmann::json old = prepared();
  old.erase("raw");
  write(old.dump());
  EXPECT_TRUE(findPreparation(train).present);
  EXPECT_FALSE(findPreparation(train).record.has_value());  // a record this version cannot read
}

// The torque noise a prepared log's record states, for its GC noise floor.
TEST(PrepareRecord, TorqueNoiseIsTheRawLevelThroughTheFilterAtTheDatasetsRate) {
  PrepareRecord r;
  r.tau_noise_rms = {0.5, 0.2};
  r.filter_order = 4;
  r.cutoff_hz = 10.0;
  r.resampled_rate = 1000.0;
  const PreparationFound found{true, r};
  std::optional<TorqueNoise> n = torqueNoiseOf(found, 1000.0, 2);
  ASSERT_TRUE(n);
  EXPECT_EQ(n->order, 4);
  EXPECT_EQ(n->cutoff, 10.0);
  EXPECT_EQ(n->sigma[1], 0.2);
  // Decimated to 250 Hz after filtering: the filtered noise keeps its variance, so the white level
  // that gives it at 250 Hz is sqrt(250 / 1000) of the raw one.
  n = torqueNoiseOf(found, 250.0, 2);
  ASSERT_TRUE(n);
  EXPECT_DOUBLE_EQ(n->sigma[0], 0.25);
  // The torque's own cutoff when prepare set one; none: white noise of the raw level.
  PreparationFound own = found;
  own.record->tau_cutoff_hz = 0.0;
  n = torqueNoiseOf(own, 250.0, 2);
  ASSERT_TRUE(n);
  EXPECT_EQ(n->order, 0);
  EXPECT_EQ(n->sigma[0], 0.5);
  // Nothing to go on: no record, an unknown level, a cutoff above the dataset's Nyquist rate,
  // another joint count.
  EXPECT_FALSE(torqueNoiseOf(PreparationFound{}, 1000.0, 2));
  PreparationFound unknown = found;
  unknown.record->tau_noise_rms[1] = std::nan("");
  EXPECT_FALSE(torqueNoiseOf(unknown, 1000.0, 2));
  EXPECT_FALSE(torqueNoiseOf(found, 15.0, 2));
  EXPECT_FALSE(torqueNoiseOf(found, 1000.0, 6));  // another robot's record
}

}  // namespace
}  // namespace dynid
