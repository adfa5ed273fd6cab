// dynid audit: do estimates of one robot from separate sessions agree within their reported
// uncertainty? Per base parameter, the spread of the estimates against their standard deviations
// (a chi-square test), the parameters that moved more than their intervals allow, grouped into
// inertial and friction terms, the session that differs most, and a verdict.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include "analysis/estimation/methods.hpp"
#include "analysis/records/model_source.hpp"
#include "core/parameters.hpp"

namespace dynid {

/// A base parameter is flagged when its chi-square test rejects agreement at this level.
inline constexpr double kDefaultAuditLevel = 0.05;
/// "The sigma are too small" (every parameter disagrees alike, rather than a few drifting): more
/// than half of the parameters' chi-squares above their median, by a sign test at this level, and
/// a median chi-square at least kAuditDispersionLimit times its expectation, with at least
/// kAuditDispersionParameters parameters tested (fewer cannot tell the two apart).
inline constexpr double kAuditSignLevel = 0.01;
inline constexpr double kAuditDispersionLimit = 1.5;
inline constexpr int kAuditDispersionParameters = 10;

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
  /// With the sigma too small: the test again with every sigma times the audit's sigma_scale (the
  /// disagreement beyond the common one); otherwise p_value.
  double p_scaled = 1.0;
  bool flagged = false;  // p_scaled < level
  int farthest = 0;      // the session whose estimate is farthest, in its own sigmas
};

struct AuditOutcome {
  std::string robot;
  nlohmann::json
      model;           // the first session's robot as a dynid JSON model (null: an older estimate)
  ModelSource source;  // and where it came from
  std::vector<std::string> sessions;  // the files, in order
  std::string method;
  std::vector<AuditParameter> parameters;
  double chi2 = 0.0, p_value = 1.0;  // over every parameter (their sum, dof summed)
  int dof = 0;
  Eigen::VectorXd session_chi2;  // each session's share of the total
  int flagged = 0, flagged_inertial = 0, flagged_friction = 0;
  double level = kDefaultAuditLevel;
  /// The median chi-square over its expectation (1 when the sessions agree within their sigma),
  /// the share of parameters above their median and its sign test's p-value; sigma_too_small when
  /// the sessions disagree alike on (nearly) every parameter, and then sigma_scale =
  /// sqrt(dispersion), by which the reported sigma are too small (1 otherwise).
  double dispersion = 1.0, above_median = 0.5, sign_p_value = 1.0, sigma_scale = 1.0;
  bool sigma_too_small = false;
  std::vector<std::string> covariance_policies;  // per session ("hac", "white")
  std::string verdict;  // "consistent", "drift in friction (Fc3, ...)", ...
  std::vector<std::string> warnings;
};

/// Reads (or identifies) every session, checks that they share the robot, drive terms and base
/// parameters, and tests their agreement. Throws InputError naming the file that differs (another
/// robot, other drive terms, other base parameters), ParseError for a malformed estimate or log.
AuditOutcome auditRun(const AuditRequest& request);

/// The test alone, on estimates and standard deviations (parameters x sessions): fills each
/// parameter's mean, chi2, p_value, p_scaled, flagged and farthest, the dispersion, the totals and
/// the verdict, which separates "the sigma are too small" (every parameter alike) from "these
/// parameters drifted" (beyond the common dispersion), and names either.
void auditTest(AuditOutcome& outcome);

}  // namespace dynid
