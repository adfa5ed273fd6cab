#include "analysis/fleet/fleet.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <random>

#include "analysis/runs/identify.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "data/puma560.hpp"
#include "tests/common/fleet_logs.hpp"
#include "tests/common/puma_runs.hpp"
#include "tests/common/trajectories.hpp"

namespace dynid {
namespace {

constexpr double kRate = 250.0;  // enough for the PUMA's base parameters from a 20 s log

/// The PUMA 560 with its drive terms, its links' inertial parameters and its drive parameters each
/// scaled by 1 + U(-5 %, 5 %) (seeded); `tool` kg more on link 6, 0.1 m along its z axis.
Model pumaOfFleet(std::uint64_t seed, double tool = 0.0) {
  Model m = makePuma560(true);
  Eigen::VectorXd theta = m.standardParameters();
  const int per = m.parameterLayout().perLink();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (int j = 0; j < m.numJoints(); ++j) {
    theta.segment(j * per, kLinkParameterCount) *= 1.0 + u(rng);
    for (int k = kLinkParameterCount; k < per; ++k) theta[j * per + k] *= 1.0 + u(rng);
  }
  theta[5 * per] += tool;
  theta[5 * per + 3] += 0.1 * tool;
  m.setStandardParameters(theta);
  return m;
}

Summary summaryOf(const Trajectory& log) {
  SummarizeRequest s;
  s.model = makePuma560(true);
  s.robot_spec = "puma560";
  s.data = &log;
  return std::move(summarizeRun(s).summaries.front());
}

std::string fleetFile(const Trajectory& data, const std::string& name) {
  const std::string path = test::tempPath(name);
  writeDatasetCsv(path, data);
  return path;
}

FleetRequest requestOf(const std::vector<Summary>& summaries) {
  FleetRequest r;
  r.model = makePuma560(true);
  r.robot_spec = "puma560";
  for (std::size_t i = 0; i < summaries.size(); ++i) {
    FleetRobotInput in;
    in.name = "robot" + std::to_string(i);
    in.summary = &summaries[i];
    r.robots.push_back(in);
  }
  return r;
}

// A robot's own estimate is identify's on its logs together: the fleet takes each robot's logs
// as summaries and merges them (ols; white: the covariance too).
TEST(FleetRun, ARobotsOwnEstimateIsIdentifysOnItsLogs) {
  const Model truth = pumaOfFleet(1);
  const std::vector<Trajectory> parts = {test::fleetLog(truth, 12.0, 11, kRate),
                                         test::fleetLog(truth, 10.0, 12, kRate)};
  FleetRequest request;
  request.model = makePuma560(true);
  request.robot_spec = "puma560";
  request.covariance = CovariancePolicy::kWhite;
  request.rest_velocity = {5e-3};  // one for both logs: the concatenation measures its own
  request.robots.push_back(
      {"a",
       {fleetFile(parts[0], "fleet_a1.csv"), fleetFile(parts[1], "fleet_a2.csv")},
       {},
       nullptr});
  for (int r = 2; r <= 3; ++r)
    request.robots.push_back({"r" + std::to_string(r),
                              {fleetFile(test::fleetLog(pumaOfFleet(r), 20.0, 10 + r, kRate),
                                         "fleet_r" + std::to_string(r) + ".csv")},
                              {},
                              nullptr});
  const FleetOutcome fleet = fleetRun(request);
  ASSERT_EQ(fleet.robots.size(), 3u);
  EXPECT_EQ(fleet.robots[0].sources.size(), 2u);
  IdentifyRequest whole;
  whole.model = makePuma560(true);
  whole.data_file = fleetFile(test::concatenated(parts, 1.0), "fleet_a_all.csv");
  whole.rest_velocity = {5e-3};
  whole.covariance = CovariancePolicy::kWhite;
  const IdentifyOutcome one = identifyRun(whole);
  const Eigen::VectorXd& beta = one.result.estimate.beta;
  // The summaries' merge is exact up to round-off in the factors (issue 70: 1e-10).
  EXPECT_LT((fleet.robots[0].alone.beta - beta).norm(), 1e-10 * beta.norm());
  EXPECT_LT((fleet.robots[0].alone.covariance - one.result.estimate.covariance).norm(),
            1e-8 * one.result.estimate.covariance.norm());
  EXPECT_EQ(fleet.robots[0].inflation, 1.0);
  EXPECT_EQ(fleet.base_names.size(), static_cast<std::size_t>(beta.size()));
}

// Eight robots of +-5 %, one with 2 kg more on link 6: that one is outside, on inertial
// parameters only, and the others inside; each inside robot's posterior lies nearer the truth than
// its own estimate on the whole.
TEST(FleetRun, FlagsTheRobotWithAToolAndShrinksTheOthers) {
  std::vector<Summary> summaries;
  std::vector<Eigen::VectorXd> truths;
  const BaseParameters base = structuralBaseParameters(makePuma560(true), StructuralOptions{});
  for (int r = 0; r < 8; ++r) {
    const Model truth = pumaOfFleet(100 + r, r == 5 ? 2.0 : 0.0);
    truths.push_back(base.project(truth.standardParameters()));
    summaries.push_back(summaryOf(test::fleetLog(truth, 20.0, 200 + r, kRate, 0.5)));
  }
  const FleetOutcome fleet = fleetRun(requestOf(summaries));
  for (int r = 0; r < 8; ++r)
    EXPECT_EQ(fleet.robots[static_cast<std::size_t>(r)].verdict.outside, r == 5) << r;
  // A tool changes inertia, not friction: every parameter outside is inertial.
  ASSERT_FALSE(fleet.robots[5].verdict.outside_parameters.empty());
  for (int k : fleet.robots[5].verdict.outside_parameters) {
    const std::string& name = fleet.base_names[static_cast<std::size_t>(k)];
    EXPECT_NE(name[0], 'F') << name;
  }
  EXPECT_NE(fleet.verdict.find("robot5"), std::string::npos) << fleet.verdict;
  double own = 0.0, shrunk = 0.0;
  for (int r = 0; r < 8; ++r) {
    if (r == 5) continue;
    const FleetRobot& robot = fleet.robots[static_cast<std::size_t>(r)];
    const Eigen::VectorXd& t = truths[static_cast<std::size_t>(r)];
    own += ((robot.alone.beta - t).array() / robot.alone.std_dev.array()).square().sum();
    shrunk += ((robot.verdict.posterior - t).array() / robot.alone.std_dev.array()).square().sum();
  }
  EXPECT_LT(shrunk, own);
}

TEST(FleetRun, RefusesARobotOfOtherDriveTermsTooFewRobotsAndOtherMethods) {
  std::vector<Summary> summaries;
  for (int r = 0; r < 3; ++r)
    summaries.push_back(summaryOf(test::fleetLog(pumaOfFleet(r), 20.0, r, kRate)));
  SummarizeRequest other;
  other.model = makePuma560(false);
  const Trajectory log = test::fleetLog(makePuma560(false), 20.0, 9, kRate);
  other.data = &log;
  summaries.push_back(std::move(summarizeRun(other).summaries.front()));
  try {
    fleetRun(requestOf(summaries));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robot3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("drive terms"), std::string::npos) << e.what();
  }
  summaries.pop_back();
  FleetRequest two = requestOf(summaries);
  two.robots.pop_back();
  EXPECT_THROW(fleetRun(two), InputError);
  FleetRequest pc = requestOf(summaries);
  pc.method = Method::kPc;
  EXPECT_THROW(fleetRun(pc), InputError);
  FleetRequest same = requestOf(summaries);
  same.robots[1].name = same.robots[0].name;
  EXPECT_THROW(fleetRun(same), InputError);
  FleetRequest none = requestOf(summaries);
  none.robots[2].summary = nullptr;
  EXPECT_THROW(fleetRun(none), InputError);
}

TEST(FleetRun, StoppedBeforeThreeRobotsItGivesNone) {
  std::vector<Summary> summaries;
  for (int r = 0; r < 3; ++r)
    summaries.push_back(summaryOf(test::fleetLog(pumaOfFleet(r), 20.0, r, kRate)));
  FleetRequest request = requestOf(summaries);
  std::atomic<bool> stop{true};
  request.control.stop = &stop;
  const FleetOutcome out = fleetRun(request);
  EXPECT_TRUE(out.interrupted);
  EXPECT_TRUE(out.robots.empty());
}

}  // namespace
}  // namespace dynid
