#include "analysis/floating/gc_measure.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>

#include "analysis/floating/gc_data.hpp"
#include "core/errors.hpp"

namespace dynid {

FloatingModel floatingEstimateModel(const FloatingModel& model, const FloatingSetEstimate& set) {
  FloatingModel out = model;
  out.setStandardParameters(
      set.physical ? set.physical->theta
                   : set.base.base.standardFromBase(set.fit.beta, model.standardParameters()));
  return out;
}

std::optional<FloatingGcData> floatingRollable(const FloatingDataset& dataset,
                                               const std::vector<Contact>& contacts,
                                               FloatingMotion motion, std::string& why) {
  why = floatingMotionRefusal(dataset);
  if (!why.empty()) return std::nullopt;
  FloatingGcData out;
  try {
    out = floatingGcData(dataset, contacts);
  } catch (const InputError& e) {
    why = e.what();
    return std::nullopt;
  }
  for (std::size_t c = 0; c < contacts.size() && !out.flags.empty(); ++c)
    if (motion == FloatingMotion::kCarried && contacts[c].body < 0 && !out.flags[c].empty()) {
      why = "the support carrying the base ('" + contacts[c].name +
            "') is known by its flag alone: it moves the base, and a flag does not say how (its "
            "wrench would)";
      return std::nullopt;
    }
  return out;
}

namespace {
/// The GC error of `candidate`, or nothing with `why` set when the data do not hold a segment of
/// the horizon asked (the only refusal left once the data and the options are checked).
std::optional<FloatingGcResult> measured(const FloatingModel& candidate, const FloatingGcData& data,
                                         const FloatingGcOptions& options, std::string& why) {
  try {
    return floatingGcError(candidate, data, options);
  } catch (const InputError& e) {
    why = e.what();
    return std::nullopt;
  }
}

}  // namespace

std::optional<ChannelVariances> floatingEstimatedVariances(const FloatingIdentifyOutcome& outcome) {
  if (outcome.method == FloatingMethod::kOls) return std::nullopt;
  std::optional<double> torque, force, moment;
  for (const FloatingSetEstimate& s : outcome.sets) {
    if (!s.refused.empty()) continue;
    if (s.variances_from == SensorSet::kTorquesAndWrenches) return s.variances;
    if (s.variances_from == SensorSet::kTorquesAndContactFlags) torque = s.variances.torque;
    if (s.variances_from == SensorSet::kWrenches)
      force = s.variances.force, moment = s.variances.moment;
  }
  if (!torque || (!outcome.contacts.empty() && !force)) return std::nullopt;
  return ChannelVariances{*torque, force.value_or(1.0), moment.value_or(1.0)};
}

double floatingGcFloor(const FloatingModel& model, const FloatingGcData& data,
                       const FloatingGcOptions& options, const ChannelVariances& v, double error,
                       std::uint64_t seed) {
  if (!(error < kMaxSegmentError)) return std::numeric_limits<double>::quiet_NaN();  // diverged
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto add = [&](Eigen::MatrixXd& m, Eigen::Index row, double sd) {
    for (Eigen::Index k = 0; k < m.cols(); ++k) m(row, k) += sd * normal(rng);
  };
  double sum = 0.0;
  for (int draw = 0; draw < kGcFloorDraws; ++draw) {
    FloatingGcData noisy = data;
    for (Eigen::Index j = 0; j < noisy.tau.rows(); ++j) add(noisy.tau, j, std::sqrt(v.torque));
    for (std::size_t c = 0; c < noisy.contacts.size(); ++c) {
      const bool frame = noisy.contacts[c].kind == Contact::Kind::kFrame;
      Eigen::MatrixXd& w = noisy.wrenches[c];
      for (Eigen::Index r = 0; r < w.rows(); ++r)
        add(w, r, std::sqrt(frame && r < 3 ? v.moment : v.force));
    }
    sum += floatingGcError(model, noisy, options).error - error;
  }
  return sum / kGcFloorDraws;
}

void measureFloatingGc(const FloatingModel& model, const FloatingIdentifyRequest& request,
                       const FloatingDataset& data, const FloatingDataset* validation,
                       FloatingIdentifyOutcome& outcome) {
  FloatingGcSummary& gc = outcome.gc;
  if (!request.gc) {
    gc.refused = "not asked (`gc`)";
    return;
  }
  if (request.combined.control.interrupted()) {  // a stop asks for the result now
    gc.refused = gc.validation_refused = "interrupted before the GC errors were measured";
    return;
  }
  const FloatingGcOptions& options = *request.gc;
  std::optional<FloatingGcData> train =
      floatingRollable(data, outcome.contacts, outcome.motion, gc.refused);
  std::optional<FloatingGcData> test;
  if (validation != nullptr)
    test = floatingRollable(*validation, outcome.contacts, outcome.motion, gc.validation_refused);
  std::optional<FloatingGcResult> r;
  if (train && (r = measured(model, *train, options, gc.refused))) {
    gc.model_train = r->error;
    gc.horizon = r->horizon;
    gc.samples_per_segment = r->samples_per_segment;
    gc.segments = static_cast<int>(r->starts.size());
    gc.linear_velocity = train->linear_velocity;
  } else {
    train.reset();
  }
  if (test && (r = measured(model, *test, options, gc.validation_refused))) {
    gc.model_test = r->error;
    gc.validation_segments = static_cast<int>(r->starts.size());
    if (!train) {
      gc.horizon = r->horizon;
      gc.samples_per_segment = r->samples_per_segment;
    }
    gc.linear_velocity = gc.linear_velocity && test->linear_velocity;
  } else {
    test.reset();
  }
  const std::optional<ChannelVariances> v = floatingEstimatedVariances(outcome);
  const std::uint64_t seed = request.structural.seed;
  if (v && train)
    gc.floor_train = floatingGcFloor(model, *train, options, *v, gc.model_train, seed);
  if (v && test)
    gc.floor_test = floatingGcFloor(model, *test, options, *v, gc.model_test, seed + 1);
  for (FloatingSetEstimate& s : outcome.sets) {
    if (!s.refused.empty() || (!train && !test)) continue;
    const FloatingModel estimate = floatingEstimateModel(model, s);
    if (train) {
      s.gc_train = floatingGcError(estimate, *train, options).error;
      if (v) s.gc_floor_train = floatingGcFloor(estimate, *train, options, *v, s.gc_train, seed);
    }
    if (test) {
      s.gc_test = floatingGcError(estimate, *test, options).error;
      if (v) s.gc_floor_test = floatingGcFloor(estimate, *test, options, *v, s.gc_test, seed + 1);
    }
  }
}

}  // namespace dynid
