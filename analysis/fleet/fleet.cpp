#include "analysis/fleet/fleet.hpp"

#include <cmath>
#include <optional>
#include <set>

#include "analysis/runs/arm.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "identifiability/least_squares_stream.hpp"

namespace dynid {

void FleetRequest::check() const {
  if (robots.empty()) throw InputError("`robots`: the fleet has no robot");
  if (method != Method::kOls && method != Method::kWls)
    throw InputError(std::string("`method` ") + methodName(method) +
                     ": a fleet takes ols or wls (its prior is Gaussian on the base parameters)");
  if (!(prior.flag_level > 0.0 && prior.flag_level <= 0.5))
    throw InputError("`flag_level` must be in (0, 0.5]");
  if (prior.max_rounds < 1) throw InputError("`max_rounds` must be >= 1");
  if (threads < 0) throw InputError("`threads` must be >= 0");
  std::set<std::string> names;
  for (const FleetRobotInput& r : robots) {
    if (r.name.empty()) throw InputError("`robots`: a robot without a name");
    if (!names.insert(r.name).second)
      throw InputError("`robots`: two robots are named '" + r.name + "'");
    const int given =
        (r.data_files.empty() ? 0 : 1) + (r.summary_files.empty() ? 0 : 1) + (r.summary ? 1 : 0);
    if (given != 1)
      throw InputError(
          "`robots`: " + r.name +
          (given == 0 ? " has no log" : " has logs and summaries: give one of the two"));
  }
  if (robots.size() < 3)
    throw InputError("`robots`: a fleet needs three robots or more to learn its spread (" +
                     std::to_string(robots.size()) + " given); one robot over time is an audit");
}

namespace {

/// The robot and its files, for messages: "robot_a (robot_a/1.csv and 2 more)".
std::string robotLabel(const FleetRobotInput& robot) {
  const std::vector<std::string>& files =
      robot.summary_files.empty() ? robot.data_files : robot.summary_files;
  if (files.empty()) return robot.name + " (its summary)";
  return robot.name + " (" + files.front() +
         (files.size() > 1 ? " and " + std::to_string(files.size() - 1) + " more" : "") + ")";
}

/// The robot's logs as one summary, read or summarized here (a summary in memory is used where
/// it is); nullopt when stopped.
std::optional<Summary> robotSummary(const FleetRequest& request, const FleetRobotInput& robot) {
  std::vector<Summary> parts;
  std::vector<std::string> names;
  if (!robot.summary_files.empty()) {
    for (const std::string& file : robot.summary_files) parts.push_back(readSummary(file));
    names = robot.summary_files;
  } else {
    SummarizeRequest s;
    s.model = request.model;
    s.robot_spec = request.robot_spec;
    s.data_files = robot.data_files;
    s.rest_velocity = request.rest_velocity;
    s.torque_filter = request.torque_filter;
    s.structural = request.structural;
    s.threads = request.threads;
    s.control = request.control;
    s.control.progress = nullptr;  // one line per robot, below
    SummarizeOutcome o = summarizeRun(s);
    if (o.interrupted) return std::nullopt;
    parts = std::move(o.summaries);
    names = robot.data_files;
  }
  std::vector<const Summary*> all;
  for (const Summary& s : parts) all.push_back(&s);
  return mergeSummaries(all, names);
}

/// InputError unless `summary` is of the fleet's robot and base parameters.
void checkSameRobot(const FleetRequest& request, const BaseParameters& base,
                    const std::vector<std::string>& base_names, const Summary& summary,
                    const FleetRobotInput& robot) {
  const std::string what = robotLabel(robot);
  std::string why = kinematicsDifference(summary.model, request.model, "the fleet's robot");
  if (why.empty() && summary.model.driveTerms().mask != request.model.driveTerms().mask)
    why = "its drive terms are " + driveTermsText(summary.model.driveTerms()) + ", the fleet's " +
          driveTermsText(request.model.driveTerms());
  if (why.empty() && (summary.base_names != base_names ||
                      jointSupport(base, request.model).support != summary.factors.support()))
    why = "its base parameters are not the fleet's (other structural options)";
  if (!why.empty()) throw InputError(what + " is not of the fleet's robot: " + why);
}

/// The robot's own estimate from its summary, its covariance as the request's policy gives it.
FleetRobot estimateRobot(const FleetRequest& request, const BaseParameters& base,
                         const FleetRobotInput& input, const Summary& summary) {
  FleetRobot out;
  out.name = input.name;
  out.sources = summary.sources;
  out.samples = summary.factors.numSamples();
  LeastSquaresStream stream(base, request.model);
  summary.factors.addTo(stream);
  const bool weighted = request.method == Method::kWls;
  try {
    out.alone =
        stream.estimate(weighted ? LeastSquaresMethod::kWeighted : LeastSquaresMethod::kOrdinary);
  } catch (const NumericalError& e) {
    throw NumericalError(robotLabel(input) + ": its logs do not determine its base parameters " +
                         "alone (" + e.what() + "); give it a longer or more exciting log");
  } catch (const InputError& e) {
    throw InputError(robotLabel(input) + ": its logs do not determine its base parameters alone (" +
                     e.what() + "); give it a longer log");
  }
  if (request.covariance == CovariancePolicy::kHac) {
    BaseEstimate robust = out.alone;
    try {
      const CovarianceSummary c =
          applyHacCovariance(summary.factors, scoreWeights(out.alone, weighted), robust);
      out.inflation = std::max(1.0, c.inflation);
    } catch (const NumericalError&) {
      out.inflation = 1.0;  // a batch that alone sees a direction: the white covariance as it is
    }
    const double f2 = out.inflation * out.inflation;
    out.alone.covariance *= f2;
    out.alone.std_dev *= out.inflation;
    out.alone.relative_std_dev_percent *= out.inflation;
  }
  return out;
}

}  // namespace

FleetOutcome fleetRun(const FleetRequest& request) {
  request.check();
  FleetOutcome out;
  out.model = request.model;
  out.model_source = modelSourceOf(request.robot_spec);
  out.robot_spec = request.robot_spec;
  out.method = request.method;
  out.covariance = request.covariance;
  out.options = request.prior;
  const BaseParameters base = structuralBaseParameters(request.model, request.structural);
  for (int j = 0; j < base.numBase(); ++j) {
    out.base_names.push_back(base.baseName(j));
    out.base_expressions.push_back(base.expression(j));
  }
  out.model_beta = base.project(request.model.standardParameters());
  const std::size_t n = request.robots.size();
  for (std::size_t i = 0; i < n; ++i) {
    const FleetRobotInput& robot = request.robots[i];
    request.control.say("fleet: " + robot.name + " (" + std::to_string(i + 1) + " of " +
                        std::to_string(n) + ")");
    std::optional<Summary> read;
    if (!robot.summary) read = robotSummary(request, robot);
    if ((!robot.summary && !read) || request.control.check()) {
      out.interrupted = true;
      break;
    }
    const Summary& summary = robot.summary ? *robot.summary : *read;
    checkSameRobot(request, base, out.base_names, summary, robot);
    out.robots.push_back(estimateRobot(request, base, robot, summary));
  }
  if (out.interrupted && out.robots.size() < 3) {
    out.robots.clear();
    return out;
  }
  std::vector<FleetMember> members;
  for (const FleetRobot& r : out.robots)
    members.push_back({r.name, r.alone.beta, r.alone.covariance});
  out.prior = fleetPrior(members, request.prior);
  for (std::size_t r = 0; r < out.robots.size(); ++r) out.robots[r].verdict = out.prior.robots[r];
  if (!out.prior.converged)
    out.warnings.push_back(
        "the robots outside the fleet would leave fewer than half of it (or three) to learn the "
        "prior from, or the set did not settle in " +
        std::to_string(request.prior.max_rounds) +
        " rounds: these robots are not one population of one model (another model, drive or "
        "controller?); the prior is the last round's");
  for (const FleetRobot& r : out.robots)
    if (r.sources.size() == 1 && r.samples < 4 * base.numBase())
      out.warnings.push_back(r.name + " has one log of " + std::to_string(r.samples) +
                             " samples: its own estimate is barely determined, the prior's is "
                             "mostly the fleet's");
  out.verdict = fleetVerdict(out);
  return out;
}

std::string fleetVerdict(const FleetOutcome& o) {
  std::vector<const FleetRobot*> outside;
  for (const FleetRobot& r : o.robots)
    if (r.verdict.outside) outside.push_back(&r);
  const std::string fleet = std::to_string(o.robots.size()) + " robots, " +
                            std::to_string(o.base_names.size()) + " base parameters";
  if (outside.empty())
    return "every robot lies inside the fleet (" + fleet + "; no p below " +
           formatNumber(o.prior.test_level, 3) + ")";
  std::string s = std::to_string(outside.size()) + " of " + std::to_string(o.robots.size()) +
                  (outside.size() == 1 ? " robots lies" : " robots lie") + " outside the fleet: ";
  for (std::size_t i = 0; i < outside.size(); ++i) {
    const FleetRobot& r = *outside[i];
    const int k = r.verdict.farthest;
    s += (i ? "; " : "") + r.name + " (" + o.base_names[static_cast<std::size_t>(k)] + " z " +
         formatNumber(r.verdict.z[k], 3);
    const std::size_t more = r.verdict.outside_parameters.size() - 1;
    if (more > 0) s += " and " + std::to_string(more) + " more";
    s += ")";
  }
  return s;
}

}  // namespace dynid
