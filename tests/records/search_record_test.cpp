#include "analysis/records/search_record.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "tests/common/sample_models.hpp"

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

TEST(SearchRecord, CheckpointRoundTripsEveryField) {
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

TEST(SearchRecord, ACheckpointResumesOnlyTheSearchWithItsSettings) {
  const SearchState s = sampleState();
  const nlohmann::json settings = {{"form", "paper"},
                                   {"budget_seconds", 3.0},
                                   {"free_parameters", {"m1", "m2", "m3", "m4", "m5"}},
                                   {"population", 2}};
  const std::string path = test::writeTemp("ck.json", checkpointJson(s, settings).dump());
  EXPECT_FALSE(readCheckpoint("", settings, "hybrid").has_value());  // no checkpoint asked for
  EXPECT_FALSE(readCheckpoint(test::tempPath("absent.json"), settings, "hybrid").has_value());
  nlohmann::json longer = settings;
  longer["budget_seconds"] = 30.0;  // a larger budget resumes
  const std::optional<SearchState> back = readCheckpoint(path, longer, "hybrid");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->best_x, s.best_x);
  nlohmann::json other = settings;
  other["form"] = "standard";
  EXPECT_THROW(readCheckpoint(path, other, "hybrid"), ParseError);  // other settings
  EXPECT_THROW(readCheckpoint(path, settings, "nlo"), ParseError);  // another method
}

TEST(SearchRecord, ACorruptCheckpointIsAParseErrorNamingTheFile) {
  nlohmann::json doc = checkpointJson(sampleState(), nlohmann::json::object());
  doc.erase("rng");
  try {
    checkpointFrom(doc, "run/ck.json");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "run/ck.json");
  }
}

}  // namespace
}  // namespace dynid
