// Every request checks its own fields against the one option table (core/option_ranges.hpp):
// its defaults pass, and a field out of range is refused under the field's name, by check() and
// by its run function before any work.
#include <gtest/gtest.h>

#include <string>

#include "analysis/logs/prepare.hpp"
#include "analysis/runs/identify.hpp"
#include "analysis/runs/search.hpp"
#include "analysis/runs/simulate.hpp"
#include "analysis/studies/demo.hpp"
#include "analysis/studies/log_study.hpp"
#include "analysis/studies/study.hpp"
#include "core/errors.hpp"
#include "data/puma560.hpp"

namespace dynid {
namespace {

/// The message check() throws, or "" when it passes.
template <typename Request>
std::string refusal(const Request& request) {
  try {
    request.check();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RequestChecks, EveryRequestsDefaultsAreWithinItsOwnRanges) {
  EXPECT_EQ(refusal(SimulateRequest{}), "");
  EXPECT_EQ(refusal(IdentifyRequest{}), "");
  EXPECT_EQ(refusal(SearchRequest{}), "");
  EXPECT_EQ(refusal(RefineRequest{}), "");
  EXPECT_EQ(refusal(StudySettings{}), "");
  EXPECT_EQ(refusal(PrepareOptions{}), "");
  EXPECT_EQ(refusal(DemoOptions{}), "");
  EXPECT_EQ(refusal(StructuralOptions{}), "");
  LogStudyRequest study;  // its datasets are required
  study.data_file = "train.csv";
  study.validate_file = "validate.csv";
  EXPECT_EQ(refusal(study), "");
}

TEST(RequestChecks, AFieldOutOfRangeIsNamedWithTheTablesRange) {
  SearchRequest search;
  search.ga.population = 1;
  EXPECT_EQ(refusal(search), "`population` must be >= 2 and <= 1e+06, not 1");
  search = {};
  search.segments.step = 1e-9;  // 0 (the sample period) or at least 1e-6
  EXPECT_EQ(refusal(search), "`step` must be 0 or >= 1e-06 and <= 10, not 1e-09");
  search = {};
  search.mass_constraint = "sometimes";
  EXPECT_NE(refusal(search).find("on, off or auto"), std::string::npos);

  RefineRequest refine;
  refine.options.max_iterations = 0;
  EXPECT_EQ(refusal(refine), "`max_iterations` must be >= 1 and <= 1e+06, not 0");

  SimulateRequest simulate;
  simulate.amplitude = Eigen::VectorXd::Constant(6, 0.5);
  simulate.amplitude[3] = 200.0;
  EXPECT_EQ(refusal(simulate), "`amplitude` must be >= 0 and <= 100, not 200");

  IdentifyRequest identify;
  identify.prior_weight = 0.0;
  EXPECT_EQ(refusal(identify), "`prior_weight` must be > 0 and <= 1e+12, not 0");
  identify = {};
  identify.structural.samples = -1;
  EXPECT_EQ(refusal(identify), "`samples` must be >= 0 and <= 1e+06, not -1");

  PrepareOptions prepare;
  prepare.trim = 1e300;  // would overflow the trimmed sample count
  EXPECT_EQ(refusal(prepare), "`trim` must be >= -1 and <= 10000, not 1e+300");

  DemoOptions demo;
  demo.threads = 1000;
  EXPECT_EQ(refusal(demo), "`threads` must be >= 0 and <= 256, not 1000");

  StudySettings settings;
  settings.search_seconds = 0.0;  // and no evaluation budget either
  EXPECT_NE(refusal(settings).find("a search needs a budget"), std::string::npos);
}

TEST(RequestChecks, RunFunctionsCheckTheirRequestBeforeAnyWork) {
  SearchRequest search;
  search.robot = makePuma560(false);
  search.data_file = "/nonexistent/never-read.csv";  // the check comes first
  search.budget.max_seconds = -1.0;
  try {
    searchRun(search);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "`budget_seconds` must be >= 0 and <= 1e+09, not -1");
  }
  IdentifyRequest identify;
  identify.model = search.robot;
  identify.data_file = search.data_file;
  identify.threads = -2;
  EXPECT_THROW(identifyRun(identify), InputError);
}

}  // namespace
}  // namespace dynid
