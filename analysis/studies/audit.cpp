#include "analysis/studies/audit.hpp"

#include <algorithm>
#include <cmath>

#include <boost/math/special_functions/gamma.hpp>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "analysis/runs/identify.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
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
  std::string file, robot, method;
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
  s.method = record.method;
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
  s.method = methodName(request.method);
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

void auditTest(AuditOutcome& o) {
  o.chi2 = 0.0;
  o.dof = 0;
  o.flagged = o.flagged_inertial = o.flagged_friction = 0;
  const Eigen::Index m = static_cast<Eigen::Index>(o.sessions.size());
  o.session_chi2 = Eigen::VectorXd::Zero(m);
  std::vector<std::string> inertial, friction;
  for (AuditParameter& p : o.parameters) {
    // A parameter with a zero deviation in some session carries no test (an unexcited column).
    if ((p.std_dev.array() <= 0.0).any()) {
      p.dof = 0;
      continue;
    }
    const Eigen::ArrayXd w = p.std_dev.array().square().inverse();
    p.mean = (w * p.estimate.array()).sum() / w.sum();
    const Eigen::ArrayXd z2 = (p.estimate.array() - p.mean).square() * w;
    p.chi2 = z2.sum();
    p.dof = static_cast<int>(m - 1);
    p.p_value = boost::math::gamma_q(0.5 * p.dof, 0.5 * p.chi2);
    p.flagged = p.p_value < o.level;
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
  o.p_value = o.dof > 0 ? boost::math::gamma_q(0.5 * o.dof, 0.5 * o.chi2) : 1.0;
  // Consistent: the overall test passes and no more parameters are flagged than chance flags
  // (level x parameters, rounded up).
  const int expected =
      static_cast<int>(std::ceil(o.level * static_cast<double>(o.parameters.size())));
  const auto list = [](const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < 8; ++i) out += (i ? ", " : "") + names[i];
    if (names.size() > 8) out += ", ...";
    return out;
  };
  if (o.p_value >= o.level && o.flagged <= expected) {
    o.verdict = "consistent";
  } else {
    std::string v;
    if (!inertial.empty()) v = "drift in inertial parameters (" + list(inertial) + ")";
    if (!friction.empty())
      v += (v.empty() ? "" : " and ") + std::string("drift in friction (") + list(friction) + ")";
    if (v.empty()) v = "inconsistent overall (no single parameter stands out)";
    o.verdict = v;
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
  o.warnings.push_back(
      "the test trusts each estimate's reported standard deviations: least squares assumes white "
      "residuals, and filtered logs' residuals are correlated, which makes them too small and "
      "flags agreement as drift");
  return o;
}

}  // namespace dynid
