#include "analysis/floating/combined.hpp"

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "analysis/floating/gc_measure.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {
namespace {

/// The pc problem of `physical` as the combined estimator's torque term over the floating
/// standard vector: F at theta widened by the problem's own base-body drive entries (which no
/// data reach: held where pc left them), its derivatives restricted to theta's entries, and T0 the
/// whole data's chi-square / 2 at pc's estimate (the unexplained part included).
TorqueTerm floatingTorqueTerm(const FloatingPhysicalEstimate& physical) {
  const std::shared_ptr<const PhysicalProblem> problem = physical.problem;
  const Eigen::VectorXd widened = physical.widened;
  const int p = static_cast<int>(physical.theta.size());
  const int drives = static_cast<int>(widened.size()) - p;
  TorqueTerm out;
  out.cost = [problem, widened](const Eigen::VectorXd& theta) {
    return problem->cost(widenFloating(theta, widened));
  };
  out.derivatives = [problem, widened, p, drives](const Eigen::VectorXd& theta, Eigen::VectorXd* g,
                                                  Eigen::MatrixXd* h) {
    Eigen::VectorXd gw;
    Eigen::MatrixXd hw;
    problem->derivatives(widenFloating(theta, widened), &gw, &hw);
    const Eigen::Index rest = p - kLinkParameterCount, from = kLinkParameterCount + drives;
    *g = narrowFloating(gw, p);
    h->resize(p, p);
    h->topLeftCorner(kLinkParameterCount, kLinkParameterCount) =
        hw.topLeftCorner(kLinkParameterCount, kLinkParameterCount);
    h->topRightCorner(kLinkParameterCount, rest) = hw.block(0, from, kLinkParameterCount, rest);
    h->bottomLeftCorner(rest, kLinkParameterCount) = hw.block(from, 0, rest, kLinkParameterCount);
    h->bottomRightCorner(rest, rest) = hw.block(from, from, rest, rest);
  };
  out.scale = 0.5 * (problem->A * widened - problem->b).squaredNorm() + physical.unexplained;
  return out;
}

/// The combinations the rollouts depend on: every row of every floating motion (the carried
/// class's torques_wrenches, the base moved anyhow, no contact but the support's).
Eigen::MatrixXd rolloutProjection(const FloatingModel& model, const StructuralOptions& structural) {
  const FloatingStructuralOptions options{structural, {}, FloatingMotion::kCarried};
  return floatingStructuralBase(model, {SensorSet::kTorquesAndWrenches}, options)
      .front()
      .base.coordinates()
      .projection;
}

/// The GC term's noise floor for every set: the one the inputs' noise gives the pc estimate of
/// torques_wrenches (every channel read: the estimate nearest the robot), else of the first set
/// estimated; 0 where that is not finite or below 0. A start far from the robot can have a floor
/// below zero (its rollouts are off by more than the noise, which then moves them towards the
/// record as often as away): no floor for a candidate near the robot, which the estimate moves to.
double floorOfNearest(const FloatingModel& model, const FloatingGcData& data,
                      const FloatingGcOptions& options, const ChannelVariances& variances,
                      const GcTerm& term, const FloatingIdentifyOutcome& outcome,
                      const FloatingIdentifyRequest& request) {
  const FloatingSetEstimate* nearest = nullptr;
  for (const FloatingSetEstimate& s : outcome.sets)
    if (s.refused.empty() && s.physical &&
        (nearest == nullptr || s.base.set == SensorSet::kTorquesAndWrenches))
      nearest = &s;
  if (nearest == nullptr) return 0.0;
  FloatingModel start = model;
  start.setStandardParameters(nearest->physical->theta);
  const double floor =
      floatingGcFloor(start, data, options, variances, term.error(nearest->physical->theta, {}),
                      request.structural.seed);
  return std::isfinite(floor) ? std::max(floor, 0.0) : 0.0;
}

}  // namespace

FloatingGcData checkCombinedData(const FloatingDataset& data, const std::vector<Contact>& contacts,
                                 FloatingMotion motion) {
  std::string why;
  std::optional<FloatingGcData> rolled = floatingRollable(data, contacts, motion, why);
  if (!rolled) throw InputError("`method`: combined rolls the data's motion out, and " + why);
  return std::move(*rolled);
}

void combineFloatingSets(const FloatingModel& model, const FloatingIdentifyRequest& request,
                         const FloatingDataset& data, const FloatingDataset* validation,
                         FloatingIdentifyOutcome& outcome) {
  const FloatingGcData rolled = checkCombinedData(data, outcome.contacts, outcome.motion);
  const std::optional<ChannelVariances> variances = floatingEstimatedVariances(outcome);
  if (!variances)
    outcome.warnings.push_back(
        "combined: no noise floor for the GC term (the GC error is fitted whatever the inputs' "
        "noise causes): the sets estimated do not give every channel's noise the rollouts read; "
        "add torques_wrenches to `sensors`, which reads them all");
  const FloatingGcOptions& gc = *request.gc;
  const Eigen::MatrixXd projection = rolloutProjection(model, request.structural);
  GcTerm term;
  try {
    term = floatingGcTerm(model, rolled, gc, projection, request.threads);
  } catch (const InputError& e) {
    throw InputError(std::string("`method`: combined rolls the data's motion out, and ") +
                     e.what());
  }
  const double floor =
      variances ? floorOfNearest(model, rolled, gc, *variances, term, outcome, request) : 0.0;
  for (FloatingSetEstimate& s : outcome.sets) {
    if (!s.refused.empty() || !s.physical) continue;
    const std::string name = sensorSetName(s.base.set);
    request.combined.control.say(std::string("identify: combined on ") + name);
    CombinedOptions options = request.combined;
    options.num_threads = request.threads;
    options.given_floor = floor;
    try {
      s.combined =
          refineCombinedTerms(floatingTorqueTerm(*s.physical), term, s.physical->theta, options);
    } catch (const NumericalError& e) {
      outcome.warnings.push_back(name + ": combined kept pc's estimate: " + e.what());
      continue;
    }
    s.physical->theta = s.combined->theta;
    s.physical->beta = s.base.base.project(s.combined->theta);
    s.fit.beta = s.physical->beta;
    measureSetEstimate(model, outcome.contacts, data, validation, s);
  }
}

}  // namespace dynid
