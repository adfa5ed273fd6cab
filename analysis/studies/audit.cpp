#include "analysis/studies/audit.hpp"

#include <algorithm>
#include <cmath>

#include <boost/math/special_functions/beta.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/runs/identify.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/robots.hpp"

namespace dynid {

void AuditRequest::check() const {
  const bool estimates = !estimate_files.empty(), logs = !data_files.empty();
  if (estimates == logs)
    throw InputError("give the sessions as estimates (`estimates`) or as logs (`data`), not both");
  if (std::max(estimate_files.size(), data_files.size()) < 2)
    throw InputError("an audit needs two sessions or more");
  if (logs && robot.empty()) throw InputError("logs need the robot they are identified with");
  if (!(level > 0.0 && level <= 0.5)) throw InputError("`level` must be in (0, 0.5]");
}

namespace {

/// A session's base parameters: names, expressions, estimates and standard deviations.
struct Session {
  std::string file, robot, method, covariance_policy;
  nlohmann::json model;  // its robot, as the estimate embeds it (null before estimate.json 5)
  ModelSource source;
  std::vector<std::string> drive_terms, names, expressions;
  Eigen::VectorXd estimate, std_dev;
};

Session readEstimate(const std::string& file) {
  const nlohmann::json document = parseJson(readFile(file), file);
  const EstimateRecord record = estimateRecordFrom(document, file);  // the strict checks
  const BaseParametersRecord base = baseParametersFrom(document, file);
  Session s;
  s.file = file;
  s.robot = record.robot_spec;
  s.model = record.model;
  s.source = {record.robot_spec, record.model_file, record.model_sha256};
  s.method = record.method;
  s.covariance_policy = record.covariance_policy;
  s.drive_terms = record.drive_terms;
  s.names = base.names;
  s.expressions = base.expressions;
  s.estimate = base.estimate;
  s.std_dev = base.std_dev;
  return s;
}

Session identifyLog(const AuditRequest& request, const std::string& file) {
  RobotOptions options;
  options.drive_terms = request.drive_terms;
  IdentifyRequest identify;
  identify.model = loadRobot(request.robot, options);
  identify.method = request.method;
  identify.data_file = file;
  identify.robot_spec = request.robot;
  identify.threads = request.threads;
  const IdentifyOutcome o = identifyRun(identify);
  Session s;
  s.file = file;
  s.robot = request.robot;
  s.model = nlohmann::json::parse(modelToJson(identify.model));
  s.source = modelSourceOf(request.robot);
  s.method = methodName(request.method);
  s.covariance_policy = o.result.covariance.policy;
  s.drive_terms = driveTermsKeys(identify.model.driveTerms());
  for (int j = 0; j < o.base.numBase(); ++j) {
    s.names.push_back(o.base.baseName(j));
    s.expressions.push_back(o.base.expression(j));
  }
  s.estimate = o.result.estimate.beta;
  s.std_dev = o.result.estimate.std_dev;
  return s;
}

bool isFriction(const std::string& name) {
  for (const char* prefix : {"Fv", "Fc", "Fa", "Fs", "Fo"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

}  // namespace

namespace {

/// Each parameter's chi-square against the inverse-variance weighted mean, unscaled.
void chiSquares(AuditOutcome& o) {
  for (AuditParameter& p : o.parameters) {
    // A parameter with a zero deviation in some session carries no test (an unexcited column).
    if ((p.std_dev.array() <= 0.0).any()) {
      p.dof = 0;
      continue;
    }
    const Eigen::ArrayXd w = p.std_dev.array().square().inverse();
    p.mean = (w * p.estimate.array()).sum() / w.sum();
    p.chi2 = ((p.estimate.array() - p.mean).square() * w).sum();
    p.dof = static_cast<int>(o.sessions.size()) - 1;
    p.p_value = boost::math::gamma_q(0.5 * p.dof, 0.5 * p.chi2);
  }
}

/// Whether the sigma are too small alike: the sign test on the parameters' chi-squares against
/// their median, and the median chi-square over its expectation.
void dispersion(AuditOutcome& o) {
  std::vector<double> ratios;
  int above = 0;
  for (const AuditParameter& p : o.parameters) {
    if (p.dof <= 0) continue;
    const double median = 2.0 * boost::math::gamma_q_inv(0.5 * p.dof, 0.5);
    ratios.push_back(p.chi2 / median);
    if (p.chi2 > median) ++above;
  }
  const int m = static_cast<int>(ratios.size());
  o.dispersion = 1.0;
  o.above_median = m > 0 ? static_cast<double>(above) / m : 0.5;
  o.sign_p_value = 1.0;
  o.sigma_too_small = false;
  o.sigma_scale = 1.0;
  if (m < kAuditDispersionParameters) return;
  std::nth_element(ratios.begin(), ratios.begin() + m / 2, ratios.end());
  o.dispersion = ratios[static_cast<std::size_t>(m / 2)];
  // P(Binomial(m, 1/2) >= above).
  o.sign_p_value = above > 0 ? boost::math::ibeta(above, m - above + 1, 0.5) : 1.0;
  o.sigma_too_small = o.sign_p_value < kAuditSignLevel && o.dispersion >= kAuditDispersionLimit;
  if (o.sigma_too_small) o.sigma_scale = std::sqrt(o.dispersion);
}

std::string nameList(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 8; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > 8) out += ", ...";
  return out;
}

}  // namespace

void auditTest(AuditOutcome& o) {
  o.chi2 = 0.0;
  o.dof = 0;
  o.flagged = o.flagged_inertial = o.flagged_friction = 0;
  const Eigen::Index m = static_cast<Eigen::Index>(o.sessions.size());
  o.session_chi2 = Eigen::VectorXd::Zero(m);
  chiSquares(o);
  dispersion(o);
  std::vector<std::string> inertial, friction;
  const double scale2 = o.sigma_scale * o.sigma_scale;
  for (AuditParameter& p : o.parameters) {
    p.flagged = false;
    p.p_scaled = 1.0;
    if (p.dof <= 0) continue;
    const Eigen::ArrayXd z2 =
        (p.estimate.array() - p.mean).square() * p.std_dev.array().square().inverse();
    p.p_scaled =
        o.sigma_too_small ? boost::math::gamma_q(0.5 * p.dof, 0.5 * p.chi2 / scale2) : p.p_value;
    p.flagged = p.p_scaled < o.level;
    z2.maxCoeff(&p.farthest);
    o.session_chi2 += z2.matrix();
    o.chi2 += p.chi2;
    o.dof += p.dof;
    if (p.flagged) {
      ++o.flagged;
      (p.group == "friction" ? friction : inertial).push_back(p.name);
      (p.group == "friction" ? o.flagged_friction : o.flagged_inertial) += 1;
    }
  }
  o.p_value = o.dof > 0 ? boost::math::gamma_q(0.5 * o.dof, 0.5 * o.chi2 / scale2) : 1.0;
  // Consistent: the overall test passes and no more parameters are flagged than chance flags
  // (level x parameters, rounded up).
  const int expected =
      static_cast<int>(std::ceil(o.level * static_cast<double>(o.parameters.size())));
  std::string drift;
  if (!inertial.empty()) drift = "drift in inertial parameters (" + nameList(inertial) + ")";
  if (!friction.empty())
    drift += (drift.empty() ? "" : " and ") + std::string("drift in friction (") +
             nameList(friction) + ")";
  const bool agree = o.p_value >= o.level && o.flagged <= expected;
  if (o.sigma_too_small) {
    o.verdict = "the sigma are too small (x" + formatNumber(o.sigma_scale, 3) +
                ": every parameter disagrees alike, model error or correlated residuals rather "
                "than drift)";
    if (!agree && !drift.empty()) o.verdict += "; beyond that, " + drift;
  } else if (agree) {
    o.verdict = "consistent";
  } else {
    o.verdict = drift.empty() ? "inconsistent overall (no single parameter stands out)" : drift;
  }
}

AuditOutcome auditRun(const AuditRequest& request) {
  request.check();
  std::vector<Session> sessions;
  for (const std::string& f : request.estimate_files) sessions.push_back(readEstimate(f));
  for (const std::string& f : request.data_files) sessions.push_back(identifyLog(request, f));
  const Session& first = sessions.front();
  for (const Session& s : sessions) {
    if (s.drive_terms != first.drive_terms)
      throw InputError(s.file + ": other drive terms than " + first.file +
                       ": sessions must share the robot and its drive model");
    if (s.names != first.names || s.expressions != first.expressions)
      throw InputError(s.file + ": other base parameters than " + first.file +
                       " (another robot, or other structural options)");
  }
  AuditOutcome o;
  o.robot = first.robot;
  o.model = first.model;
  o.source = first.source;
  o.method = first.method;
  o.level = request.level;
  for (const Session& s : sessions) {
    o.sessions.push_back(s.file);
    if (s.method != first.method)
      o.warnings.push_back(s.file + " was estimated by " + s.method + ", " + first.file + " by " +
                           first.method);
  }
  const Eigen::Index m = static_cast<Eigen::Index>(sessions.size());
  for (std::size_t j = 0; j < first.names.size(); ++j) {
    AuditParameter p;
    p.name = first.names[j];
    p.expression = first.expressions[j];
    p.group = isFriction(p.name) ? "friction" : "inertial";
    p.estimate.resize(m);
    p.std_dev.resize(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      p.estimate[i] = sessions[static_cast<std::size_t>(i)].estimate[static_cast<Eigen::Index>(j)];
      p.std_dev[i] = sessions[static_cast<std::size_t>(i)].std_dev[static_cast<Eigen::Index>(j)];
    }
    o.parameters.push_back(std::move(p));
  }
  auditTest(o);
  for (const Session& s : sessions) {
    o.covariance_policies.push_back(s.covariance_policy);
    if (s.covariance_policy != "hac")
      o.warnings.push_back(s.file +
                           ": its standard deviations are the white covariance's, which takes the "
                           "residuals as uncorrelated; a filtered log's are not, which makes them "
                           "too small (identify it again with the default `covariance`)");
  }
  return o;
}

}  // namespace dynid
