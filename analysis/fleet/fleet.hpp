// The fleet wing's run (dynid fleet): many robots of one model at once. Each robot's logs are
// summarized and merged (runs/summarize.hpp), or its summaries read and merged; each robot's
// least-squares estimate (ols or wls) with its covariance; the fleet's prior learnt from them
// (prior.hpp): per base parameter the fleet's mean and spread, the robots and parameters outside
// the fleet, and each robot's estimate with the prior (its posterior). One robot over time is
// studies/audit.hpp's; nothing here prints or writes a report.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "analysis/estimation/covariance.hpp"
#include "analysis/estimation/methods.hpp"
#include "analysis/estimation/training_rows.hpp"
#include "analysis/fleet/prior.hpp"
#include "analysis/records/summary_record.hpp"
#include "core/model.hpp"
#include "core/run_control.hpp"
#include "identifiability/base_estimate.hpp"
#include "identifiability/base_parameters.hpp"

namespace dynid {

/// One robot of the fleet: its name and its logs, or summaries of them (one of the two).
struct FleetRobotInput {
  std::string name;
  std::vector<std::string> data_files;
  std::vector<std::string> summary_files;
  /// Or its summary in memory (the Python module's; not owned): the others then empty.
  const Summary* summary = nullptr;
};

struct FleetRequest {
  Model model;             // the robot model every member is (with its drive terms)
  std::string robot_spec;  // how it was named, recorded
  std::vector<FleetRobotInput> robots;
  Method method = Method::kOls;  // ols or wls: the prior is Gaussian on the base parameters
  /// Each robot's covariance: hac, the white one's shape widened by the robust covariance's median
  /// inflation over the white (prior.hpp needs it of full rank, which a batch-means sandwich of a
  /// short log's few batches is not); white, as it is.
  CovariancePolicy covariance = CovariancePolicy::kHac;
  std::vector<double> rest_velocity;  // each log's, as summarize (empty: measured on each)
  TorqueFilterChoice torque_filter;   // each log's, as summarize
  StructuralOptions structural;
  FleetOptions prior;
  int threads = 0;  // 0: every core; the same result for any count
  RunControl control;
  /// Throws InputError naming the first bad field.
  void check() const;
};

struct FleetRobot {
  std::string name;
  std::vector<SummarySource> sources;  // its logs
  long long samples = 0;
  BaseEstimate alone;      // its own estimate, its covariance as the fleet takes it
  double inflation = 1.0;  // hac: the factor its white sigma were widened by
  FleetVerdict verdict;
};

struct FleetOutcome {
  Model model;
  ModelSource model_source;
  std::string robot_spec;
  Method method = Method::kOls;
  CovariancePolicy covariance = CovariancePolicy::kHac;
  FleetOptions options;
  std::vector<std::string> base_names, base_expressions;
  Eigen::VectorXd model_beta;  // the model's own base parameters
  FleetPrior prior;
  std::vector<FleetRobot> robots;
  std::string verdict;  // one sentence: the robots outside the fleet, or none
  std::vector<std::string> warnings;
  /// Stopped (control) before every robot was estimated: the fleet of those done (three or
  /// more), or none (`robots` empty).
  bool interrupted = false;
};

/// The fleet of the request's robots. Throws InputError naming the robot and its file for a log or
/// summary of another robot model, other drive terms or base parameters, a robot without logs or
/// whose logs do not determine its base parameters, two robots of one name, fewer than three
/// robots; what summarize and the summaries' reader throw.
FleetOutcome fleetRun(const FleetRequest& request);

/// The verdict sentence of `outcome`'s prior and robots.
std::string fleetVerdict(const FleetOutcome& outcome);

}  // namespace dynid
