#include "core/option_ranges.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {

// The ranges shared by options of several commands (one definition each).
constexpr OptionRange kNonNegative{0.0, kNoOptionLimit, false, false};
constexpr OptionRange kSeconds{0.0, 1e9, false, false};       // a wall-time budget, 0: none
constexpr OptionRange kEvaluations{0.0, 1e12, false, false};  // an evaluation budget, 0: none
constexpr OptionRange kFraction{0.0, 0.999, false, false};    // a perturbation or hold-out
constexpr OptionRange kHorizon{0.0, 1e4, true, false};
constexpr OptionRange kSegments{0.0, 1e6, false, false};
constexpr OptionRange kRangeFactor{0.0, 1e3, false, false};
constexpr OptionRange kIterations{0.0, 1e6, false, false};
constexpr OptionRange kAtLeastOneIteration{1.0, 1e6, false, false};

constexpr OptionRule kOptionRules[] = {
    // simulate
    {"", "duration", {0.0, 1e6, true, false}, "simulated time [s]"},
    {"", "dt", {1e-7, 1.0, false, false}, "integration step [s]"},
    {"simulate", "rate", {0.0, 1e6, true, false}, "recording and control rate [Hz]"},
    {"", "noise-q", kNonNegative, "std. dev. of noise on recorded q [rad]"},
    {"", "noise-dq", kNonNegative, "... on recorded dq [rad/s]"},
    {"", "noise-tau", kNonNegative, "... on recorded tau [N m]"},
    {"", "noise-force", kNonNegative, "... on recorded contact forces [N] (a floating base)"},
    {"", "noise-moment", kNonNegative, "... on recorded contact moments [N m] (a floating base)"},
    {"simulate", "samples", {1.0, 1e6, false, false}, "a floating base's states, one a row"},
    {"simulate",
     "friction-cone",
     {0.0, 1e3, false, false},
     "a floating base holding: the ground's friction coefficient mu; the contacts' forces the "
     "least-norm ones within cones about its normal, a state they cannot hold drawn again (0: no "
     "cones)"},
    {"",
     "amplitude",
     {0.0, 100.0, false, false},
     "amplitude per joint [rad] (one value for all); fourier: excursion bound"},
    {"", "base-frequency", {0.0, 1e3, true, false}, "fourier: base frequency [Hz]"},
    {"", "harmonics", {1.0, 1000.0, false, false}, "fourier: number of harmonics"},
    {"", "bandwidth", {0.0, 1e4, true, false}, "bandwidth for default gains [Hz]"},
    {"", "controller-perturb", kFraction,
     "perturb the controller model's parameters by up to this fraction (seeded)"},
    // the structural analysis (identifiability, identify, excite)
    {"",
     "samples",
     {0.0, 1e6, false, false},
     "random states for the structural analysis (0: max(100, 5 p / n))"},
    {"",
     "tolerance",
     {0.0, 1.0, false, false},
     "rank tolerance on |R_jj| of the unit-column W (0: 1e-8 max|R_jj|)"},
    {"",
     "prior-weight",
     {0.0, 1e12, true, false},
     "pc: weight of the divergence from the prior, in chi-square units"},
    // search
    {"", "perturb", kFraction,
     "initial estimate: the robot's parameters perturbed uniformly by up to this fraction"},
    {"", "budget-evals", kEvaluations, "stop after this many GC evaluations"},
    {"", "budget-seconds", kSeconds, "stop after this wall time [s]"},
    {"", "gc-tolerance", kNonNegative, "stop at this GC error"},
    {"", "range", kRangeFactor, "bounds: initial estimate +- this fraction"},
    {"",
     "absolute-range",
     {0.0, 1e6, false, false},
     "range of parameters whose initial estimate is 0 (0: they stay fixed)"},
    {"",
     "total-mass",
     {0.0, 1e6, true, false},
     "total mass [kg] (default: the truth's, else the initial's)"},
    {"", "horizon", kHorizon, "prediction horizon [s]"},
    {"", "segments", kSegments, "segments (0: all non-overlapping)"},
    {"", "step", {1e-6, 10.0, false, true}, "integration step [s] (0: sample period)"},
    {"", "population", {2.0, 1e6, false, false}, "GA population"},
    {"", "elites", {0.0, 1e6, false, false}, "GA elites"},
    {"", "migration", {0.0, 1.0, false, false}, "GA migration factor"},
    {"", "mutation-rate", {0.0, 1.0, false, false}, "GA per-parameter mutation rate"},
    {"", "mutation-scale", {0.0, 1e3, false, false}, "mutation sigma / |value| (GA and NLO)"},
    {"", "evals-per-seed", {1.0, 1e9, false, false}, "NLO COBYLA evaluations per seed"},
    // refine
    {"refine", "budget-seconds", kSeconds, "stop after this time (0: none)"},
    {"refine", "range", kRangeFactor, "from estimate.json: bounds, start +- this fraction"},
    {"refine", "horizon", kHorizon, "from estimate.json: prediction horizon [s]"},
    {"refine", "segments", kSegments, "from estimate.json: segments"},
    {"", "max-iterations", {1.0, 1e6, false, false}, "Levenberg-Marquardt iterations per stage"},
    {"",
     "continuity-weight",
     {0.0, 1e12, false, false},
     "with --estimate-initial-states: weight of the gap between a segment's predicted end and the "
     "next segment's start where they meet (contiguous segments, multiple shooting); 0 keeps the "
     "measured end states"},
    // study, demo and batch
    {"study", "horizon", kHorizon, "GC error horizon [s]"},
    {"study", "segments", {1.0, 1e6, false, false}, "GC error segments (at most that fit)"},
    {"", "search-seconds", kSeconds, "wall time of each search"},
    {"demo", "search-seconds", kSeconds, "wall time of each search (0: 30 s, 2 s with --quick)"},
    {"", "search-evaluations", kEvaluations, "GC evaluations of each search"},
    {"demo", "search-evaluations", kEvaluations,
     "GC evaluations of each search (0: no limit); alone, it replaces the time limit, so the "
     "table is the same on every machine for a seed"},
    {"", "refine-iterations", kIterations, "per refinement stage (0: 200, 30 with --quick)"},
    {"study", "refine-iterations", kAtLeastOneIteration, "per refinement stage"},
    {"", "refine-seconds", kSeconds, "per refinement (0: no limit)"},
    {"",
     "refine-tolerance",
     {0.0, 1.0, false, false},
     "relative cost change that ends a refinement"},
    {"",
     "combined-weight",
     {0.0, 1e6, false, false},
     "combined: the GC term's weight relative to the torque term's, each normalised by its "
     "value at the pc estimate"},
    {"",
     "front-tolerance",
     {0.0, 10.0, false, false},
     "the chosen estimate's held-out torque error may exceed the best physically consistent one's "
     "by this fraction of it"},
    {"", "combined-seconds", kSeconds, "combined: wall time (0: no limit)"},
    {"", "combined-iterations", kAtLeastOneIteration, "combined: Levenberg-Marquardt iterations"},
    // prepare
    {"prepare", "rate", {1e-3, 1e7, false, true}, "resampling rate [Hz] (0: median)"},
    {"prepare",
     "contact-threshold",
     {0.0, 1e7, false, false},
     "a floating base: contact flags from the wrenches, a frame holding where its "
     "low-passed force's norm reaches this [N] (0: none)"},
    {"", "joints", {0.0, 1000.0, false, false}, "joints (files: required)"},
    {"", "order", {1.0, 12.0, false, false}, "Butterworth order"},
    {"", "decimate", {1.0, 1e6, false, false}, "keep every Nth sample"},
    {"", "max-gap", {0.0, 1e6, false, false}, "split at longer steps [s] (0: 5 steps)"},
    {"", "validate-fraction", kFraction, "hold out the last fraction of each run as validate.csv"},
    {"", "trim", {-1.0, 1e4, false, false}, "dropped at run ends [s] (< 0: 2/cutoff)"},
    {"", "savgol-window", {0.0, 1e5, false, false}, "savgol: odd samples (0: auto)"},
    {"", "savgol-degree", {2.0, 6.0, false, false}, "savgol: polynomial degree"},
    // excite
    // payload
    {"payload",
     "payload-mass",
     {0.0, 1e5, true, false},
     "the payload's known mass: drive gains from a loaded and an unloaded run [kg]"},
    {"payload",
     "max-motion-difference",
     {0.0, 10.0, true, false},
     "largest RMS position difference of a joint between the loaded and the unloaded run [rad]"},
    // audit
    {"audit", "level", {0.0, 0.5, true, false}, "significance level of each parameter's test"},
    // monitor
    {"monitor",
     "false-alarms-per-hour",
     {0.0, 1e6, true, false},
     "--calibration: false alarms per hour of the whole arm the thresholds are set for"},
    {"monitor",
     "hold",
     {0.0, 1e3, false, false},
     "an event ends once every residual has stayed below its threshold this long [s]"},
    {"monitor",
     "max-gap",
     {0.0, 1e6, true, false},
     "a step between samples longer than this restarts the observer [s]"},
    {"excite", "period", {0.0, 1e4, true, false}, "period of the motion [s]"},
    {"excite",
     "payload-proximal-share",
     {0.0, 1.0, true, false},
     "--payload: the share of their range the joints before the wrist may use"},
    {"excite", "harmonics", {2.0, 50.0, false, false}, "harmonics per joint"},
    {"excite",
     "starts",
     {0.0, 1e4, false, false},
     "optimiser starts (seeded random designs; 0: 8, or 16 with --payload)"},
    {"excite", "evaluations", {1.0, 1e8, false, false}, "COBYLA evaluations per start"},
    {"excite", "budget-seconds", kSeconds,
     "stop after this wall time and keep the best design [s] (0: no limit)"},
    {"excite",
     "grid-rate",
     {0.0, 1e5, true, false},
     "samples per second of the optimiser's criterion and limits [Hz]"},
    {"excite",
     "check-rate",
     {0.0, 1e6, true, false},
     "samples per second of the final limit check and the scores [Hz]"},
    {"excite", "csv-rate", {0.0, 1e6, true, false}, "samples per second of excitation.csv [Hz]"},
    {"excite", "segments", kSegments, "segments of the GC criterion's Jacobian (as dynid search)"},
    {"excite", "horizon", kHorizon, "horizon of the GC criterion's segments [s]"},
    {"excite",
     "torque-noise",
     {0.0, 1e6, true, false},
     "torque noise for the expected standard deviations [N m]"},
    {"excite",
     "torque-margin",
     {0.0, 1.0, true, false},
     "keep |tau| within this fraction of the torque limits"},
    {"excite",
     "base-radius",
     {0.0, 1e3, false, false},
     "keep the last link's origin this far from the base z axis [m]"},
    {"excite",
     "floor",
     {-1e3, 1e3, false, false},
     "keep every link origin above this height in the base frame [m] (default: no floor)"},
    // every command that runs in parallel
    {"", "threads", {0.0, 256.0, false, false}, "threads (0: all cores)"},
    {"batch", "jobs", {1.0, 256.0, false, false}, "runs at a time (worker processes)"},
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

std::string optionRangeText(const OptionRule& rule) {
  const OptionRange& r = rule.range;
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
  const OptionRange& g = r->range;
  const bool ok = (g.zero_ok && x == 0.0) || ((g.lo_open ? x > g.lo : x >= g.lo) && x <= g.hi);
  if (!ok)
    throw InputError(spelling + " must be " + optionRangeText(*r) + ", not " + formatNumber(x));
}

}  // namespace dynid
