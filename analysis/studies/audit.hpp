// dynid audit: do estimates of one robot from separate sessions agree within their reported
// uncertainty? Per base parameter, the spread of the estimates against their standard deviations
// (a chi-square test), the parameters that moved more than their intervals allow, grouped into
// inertial and friction terms, the session that differs most, and a verdict.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/estimation/methods.hpp"
#include "core/parameters.hpp"

namespace dynid {

/// A base parameter is flagged when its chi-square test rejects agreement at this level.
inline constexpr double kDefaultAuditLevel = 0.05;

/// The sessions: identify's estimate.json files, or logs identified one by one here (all with the
/// same robot, drive terms and method).
struct AuditRequest {
  std::vector<std::string> estimate_files;  // either these (two or more),
  std::vector<std::string> data_files;      // or these (two or more), with:
  std::string robot;                        // the robot (a spec) the logs are identified with
  std::optional<DriveTerms> drive_terms;    // its drive terms (default: none)
  Method method = Method::kOls;             // ols, wls or pc
  double level = kDefaultAuditLevel;        // in (0, 0.5]
  int threads = 0;
  /// Throws InputError for fewer than two sessions, both or neither kind, a level out of range.
  void check() const;
};

/// One base parameter across the sessions.
struct AuditParameter {
  std::string name, expression;
  std::string group;                  // "inertial" or "friction"
  Eigen::VectorXd estimate, std_dev;  // per session
  double mean = 0.0;                  // the inverse-variance weighted mean
  double chi2 = 0.0;                  // sum over sessions of ((estimate - mean) / std_dev)^2
  int dof = 0;                        // sessions - 1
  double p_value = 1.0;               // P(chi2_dof >= chi2)
  bool flagged = false;               // p_value < level
  int farthest = 0;                   // the session whose estimate is farthest, in its own sigmas
};

struct AuditOutcome {
  std::string robot;
  std::vector<std::string> sessions;  // the files, in order
  std::string method;
  std::vector<AuditParameter> parameters;
  double chi2 = 0.0, p_value = 1.0;  // over every parameter (their sum, dof summed)
  int dof = 0;
  Eigen::VectorXd session_chi2;  // each session's share of the total
  int flagged = 0, flagged_inertial = 0, flagged_friction = 0;
  double level = kDefaultAuditLevel;
  std::string verdict;  // "consistent", "drift in friction (Fc3, ...)", ...
  std::vector<std::string> warnings;
};

/// Reads (or identifies) every session, checks that they share the robot, drive terms and base
/// parameters, and tests their agreement. Throws InputError naming the file that differs (another
/// robot, other drive terms, other base parameters), ParseError for a malformed estimate or log.
AuditOutcome auditRun(const AuditRequest& request);

/// The test alone, on estimates and standard deviations (parameters x sessions): fills each
/// parameter's mean, chi2, p_value, flagged and farthest, and the totals and verdict.
void auditTest(AuditOutcome& outcome);

}  // namespace dynid
