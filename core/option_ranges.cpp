#include "core/option_ranges.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {

constexpr OptionRule kOptionRules[] = {
    {"", "duration", 0.0, 1e6, true, false},
    {"", "dt", 1e-7, 1.0, false, false},
    {"simulate", "rate", 0.0, 1e6, true, false},
    {"prepare", "rate", 1e-3, 1e7, false, true},
    {"", "noise-q", 0.0, kNoOptionLimit, false, false},
    {"", "noise-dq", 0.0, kNoOptionLimit, false, false},
    {"", "noise-tau", 0.0, kNoOptionLimit, false, false},
    {"", "amplitude", 0.0, 100.0, false, false},
    {"", "base-frequency", 0.0, 1e3, true, false},
    {"", "harmonics", 1.0, 1000.0, false, false},
    {"", "bandwidth", 0.0, 1e4, true, false},
    {"", "controller-perturb", 0.0, 0.999, false, false},
    {"", "perturb", 0.0, 0.999, false, false},
    {"", "budget-evals", 0.0, 1e12, false, false},
    {"", "budget-seconds", 0.0, 1e9, false, false},
    {"", "gc-tolerance", 0.0, kNoOptionLimit, false, false},
    {"", "range", 0.0, 1e3, false, false},
    {"", "absolute-range", 0.0, 1e6, false, false},
    {"", "total-mass", 0.0, 1e6, true, false},
    {"", "horizon", 0.0, 1e4, true, false},
    {"", "segments", 0.0, 1e6, false, false},
    {"study", "segments", 1.0, 1e6, false, false},
    {"", "step", 1e-6, 10.0, false, true},
    {"", "population", 2.0, 1e6, false, false},
    {"", "elites", 0.0, 1e6, false, false},
    {"", "migration", 0.0, 1.0, false, false},
    {"", "mutation-rate", 0.0, 1.0, false, false},
    {"", "mutation-scale", 0.0, 1e3, false, false},
    {"", "evals-per-seed", 1.0, 1e9, false, false},
    {"", "samples", 0.0, 1e6, false, false},
    {"", "tolerance", 0.0, 1.0, false, false},
    {"", "prior-weight", 0.0, 1e12, true, false},
    {"", "continuity-weight", 0.0, 1e12, false, false},
    {"", "search-seconds", 0.0, 1e9, false, false},
    {"", "search-evaluations", 0.0, 1e12, false, false},
    {"", "refine-iterations", 0.0, 1e6, false, false},
    {"study", "refine-iterations", 1.0, 1e6, false, false},
    {"", "refine-seconds", 0.0, 1e9, false, false},
    {"", "refine-tolerance", 0.0, 1.0, false, false},
    {"", "joints", 0.0, 1000.0, false, false},
    {"", "order", 1.0, 12.0, false, false},
    {"", "decimate", 1.0, 1e6, false, false},
    {"", "max-gap", 0.0, 1e6, false, false},
    {"", "validate-fraction", 0.0, 0.999, false, false},
    {"", "savgol-window", 0.0, 1e5, false, false},
    {"", "savgol-degree", 2.0, 6.0, false, false},
    {"excite", "period", 0.0, 1e4, true, false},
    {"excite", "harmonics", 2.0, 50.0, false, false},
    {"excite", "starts", 1.0, 1e4, false, false},
    {"excite", "evaluations", 1.0, 1e8, false, false},
    {"excite", "grid-rate", 0.0, 1e5, true, false},
    {"excite", "check-rate", 0.0, 1e6, true, false},
    {"excite", "csv-rate", 0.0, 1e6, true, false},
    {"excite", "torque-noise", 0.0, 1e6, true, false},
    {"excite", "torque-margin", 0.0, 1.0, true, false},
    {"excite", "base-radius", 0.0, 1e3, false, false},
    {"excite", "floor", -1e3, 1e3, false, false},
    {"", "threads", 0.0, 256.0, false, false},
    {"batch", "jobs", 1.0, 256.0, false, false},
    {"", "max-iterations", 1.0, 1e6, false, false},
};

}  // namespace

std::span<const OptionRule> optionRules() { return kOptionRules; }

const OptionRule* findOptionRule(std::string_view command, std::string_view name) {
  const OptionRule* generic = nullptr;
  for (const OptionRule& r : kOptionRules) {
    if (name != r.name) continue;
    if (command == r.command) return &r;
    if (r.command[0] == '\0') generic = &r;
  }
  return generic;
}

std::string optionRangeText(const OptionRule& r) {
  std::string text = r.lo_open ? "> " + formatNumber(r.lo) : ">= " + formatNumber(r.lo);
  if (r.hi < kNoOptionLimit) text += " and <= " + formatNumber(r.hi);
  if (r.zero_ok) text = "0 or " + text;
  return text;
}

void checkOption(std::string_view command, std::string_view name, double x,
                 const std::string& spelling) {
  if (!std::isfinite(x)) throw InputError(spelling + " must be a finite number");
  const OptionRule* r = findOptionRule(command, name);
  if (r == nullptr) return;
  const bool ok = (r->zero_ok && x == 0.0) || ((r->lo_open ? x > r->lo : x >= r->lo) && x <= r->hi);
  if (!ok)
    throw InputError(spelling + " must be " + optionRangeText(*r) + ", not " + formatNumber(x));
}

}  // namespace dynid
