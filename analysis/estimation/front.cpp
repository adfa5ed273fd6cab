#include "analysis/estimation/front.hpp"

#include <cmath>
#include <string>

#include "core/errors.hpp"

namespace dynid {

std::vector<double> defaultFrontWeights() {
  return {0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0};
}

void checkFrontWeights(const std::vector<double>& weights) {
  if (weights.empty()) throw InputError("`front_weights` is empty");
  for (std::size_t k = 0; k < weights.size(); ++k)
    if (!(weights[k] > 0.0) || !std::isfinite(weights[k]) ||
        (k > 0 && weights[k] <= weights[k - 1]))
      throw InputError("`front_weights` must be finite, > 0 and increasing (entry " +
                       std::to_string(k + 1) + ")");
}

std::vector<FrontPoint> combinedFront(const Model& model, const BaseParameters& base,
                                      const LeastSquaresSource& source,
                                      const LeastSquaresOutcome& pc, const GcProblem& gc,
                                      const CombinedOptions& options,
                                      const std::vector<double>& weights) {
  checkFrontWeights(weights);
  std::vector<FrontPoint> out;
  CombinedOptions point = options;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (k > 0 && options.control.stopped()) break;
    point.gc_weight = weights[k];
    FrontPoint p;
    p.weight = weights[k];
    try {
      p.estimate = combinedEstimate(model, base, source, pc, gc, point, &p.detail,
                                    out.empty() ? nullptr : &out.back().estimate.standard);
    } catch (const NumericalError&) {
      if (out.empty()) throw;
      break;  // the previous point's rollouts held, this start's not: the front ends there
    }
    if (out.empty()) {  // pc's normalisers for every later point
      point.given_gc = p.detail.initial_gc;
      point.given_floor = options.noise_floor ? p.detail.gc_floor : -1.0;
    }
    const bool stopped = options.control.stopped();
    out.push_back(std::move(p));
    if (stopped) break;
  }
  return out;
}

double HeldOutErrors::gcExcess() const {
  return gc <= kAtNoiseFloor * gc_floor ? 0.0 : gc - gc_floor;
}

FrontChoice chooseByHeldOut(const std::vector<HeldOutErrors>& candidates, double tolerance) {
  const auto usable = [](const HeldOutErrors& e) {
    return e.consistent && std::isfinite(e.torque) && std::isfinite(e.gc);
  };
  FrontChoice out;
  const int n = static_cast<int>(candidates.size());
  for (int k = 0; k < n; ++k)
    if (usable(candidates[k]) &&
        (out.best_torque < 0 || candidates[k].torque < candidates[out.best_torque].torque))
      out.best_torque = k;
  if (out.best_torque < 0) return out;
  out.torque_bound = (1.0 + tolerance) * candidates[out.best_torque].torque;
  const auto better = [](const HeldOutErrors& a, const HeldOutErrors& b) {
    if (a.gcExcess() != b.gcExcess()) return a.gcExcess() < b.gcExcess();
    return a.torque < b.torque;
  };
  for (int k = 0; k < n; ++k)
    if (usable(candidates[k]) && candidates[k].torque <= out.torque_bound &&
        (out.index < 0 || better(candidates[k], candidates[out.index])))
      out.index = k;
  out.at_floor = candidates[out.index].gcExcess() == 0.0;
  return out;
}

}  // namespace dynid
