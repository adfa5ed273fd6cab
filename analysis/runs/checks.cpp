// The requests of the runs wing (simulate, identify, search, refine) check their numeric fields
// against the one option table (core/option_ranges.hpp), under the Python module's keyword
// spellings, which are also the fields' names. The run functions call these first, so the CLI
// (which checks its flags when it parses them), the Python module and any other caller get the same
// ranges and messages.
#include <string>

#include "analysis/estimation/front.hpp"
#include "analysis/runs/identify.hpp"
#include "analysis/runs/search.hpp"
#include "analysis/runs/simulate.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "core/option_ranges.hpp"

namespace dynid {

void SimulateRequest::check() const {
  constexpr const char* kCommand = "simulate";
  checkOption(kCommand, "controller-perturb", controller_perturb, "`controller_perturb`");
  for (Eigen::Index j = 0; j < amplitude.size(); ++j)
    checkOption(kCommand, "amplitude", amplitude[j], "`amplitude`");
  checkOption(kCommand, "base-frequency", base_frequency, "`base_frequency`");
  checkOption(kCommand, "harmonics", harmonics, "`harmonics`");
  checkOption(kCommand, "bandwidth", bandwidth, "`bandwidth`");
  checkOption(kCommand, "duration", simulation.duration, "`duration`");
  checkOption(kCommand, "dt", simulation.step, "`dt`");
  checkOption(kCommand, "rate", simulation.record_rate, "`rate`");
  checkOption(kCommand, "noise-q", simulation.noise_q, "`noise_q`");
  checkOption(kCommand, "noise-dq", simulation.noise_dq, "`noise_dq`");
  checkOption(kCommand, "noise-tau", simulation.noise_tau, "`noise_tau`");
  if (pauses) pauses->check();
}

void IdentifyRequest::check() const {
  constexpr const char* kCommand = "identify";
  checkOption(kCommand, "prior-weight", prior_weight, "`prior_weight`");
  structural.check();
  checkOption(kCommand, "threads", threads, "`threads`");
  if (method == Method::kCombined) {
    checkOption(kCommand, "horizon", segments.horizon, "`horizon`");
    checkOption(kCommand, "segments", segments.num_segments, "`segments`");
    checkOption(kCommand, "combined-weight", combined.gc_weight, "`combined_weight`");
    checkOption(kCommand, "combined-seconds", combined.max_seconds, "`combined_seconds`");
    checkOption(kCommand, "combined-iterations", combined.max_iterations, "`combined_iterations`");
  }
  if (front_weights.empty()) return;
  if (method != Method::kCombined)
    throw InputError("`front_weights` sweeps the combined estimator: `method` combined, not " +
                     std::string(methodName(method)));
  checkFrontWeights(front_weights);
  checkOption(kCommand, "front-tolerance", front_tolerance, "`front_tolerance`");
  if (validate == nullptr && validate_file.empty())
    throw InputError(
        "the front's estimate is chosen on held-out data: `front_weights` needs "
        "`validate`");
}

void SummarizeRequest::check() const {
  if (data == nullptr && data_files.empty()) throw InputError("`data`: no log to summarize");
  structural.check();
  checkOption("summarize", "threads", threads, "`threads`");
}

void SearchRequest::check() const {
  constexpr const char* kCommand = "search";
  if (perturb) checkOption(kCommand, "perturb", *perturb, "`perturb`");
  if (total_mass) checkOption(kCommand, "total-mass", *total_mass, "`total_mass`");
  checkOption(kCommand, "budget-evals", static_cast<double>(budget.max_evaluations),
              "`budget_evals`");
  checkOption(kCommand, "budget-seconds", budget.max_seconds, "`budget_seconds`");
  checkOption(kCommand, "gc-tolerance", budget.gc_tolerance, "`gc_tolerance`");
  checkOption(kCommand, "range", space.relative_range, "`range`");
  checkOption(kCommand, "absolute-range", space.absolute_range, "`absolute_range`");
  checkOption(kCommand, "horizon", segments.horizon, "`horizon`");
  checkOption(kCommand, "segments", segments.num_segments, "`segments`");
  checkOption(kCommand, "step", segments.step, "`step`");
  checkOption(kCommand, "population", ga.population, "`population`");
  checkOption(kCommand, "elites", ga.elites, "`elites`");
  checkOption(kCommand, "migration", ga.migration, "`migration`");
  checkOption(kCommand, "mutation-rate", ga.mutation_rate, "`mutation_rate`");
  checkOption(kCommand, "mutation-scale", ga.mutation_scale, "`mutation_scale`");
  checkOption(kCommand, "mutation-scale", nlo.mutation_scale, "`mutation_scale`");
  checkOption(kCommand, "evals-per-seed", nlo.evaluations_per_seed, "`evals_per_seed`");
  checkOption(kCommand, "threads", threads, "`threads`");
  if (mass_constraint != "on" && mass_constraint != "off" && mass_constraint != "auto")
    throw InputError("mass_constraint must be on, off or auto, not '" + mass_constraint + "'");
}

void RefineRequest::check() const {
  constexpr const char* kCommand = "refine";
  checkOption(kCommand, "continuity-weight", options.continuity_weight, "`continuity_weight`");
  checkOption(kCommand, "max-iterations", options.max_iterations, "`max_iterations`");
  checkOption(kCommand, "budget-seconds", options.max_seconds, "`budget_seconds`");
  checkOption(kCommand, "threads", options.num_threads, "`threads`");
  checkOption(kCommand, "range", range, "`range`");
  checkOption(kCommand, "horizon", horizon, "`horizon`");
  checkOption(kCommand, "segments", segments, "`segments`");
}

}  // namespace dynid
