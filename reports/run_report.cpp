#include "reports/run_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/search_record.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/model_report.hpp"

namespace dynid {

using nlohmann::json;

namespace {
/// A held-out dataset's GC errors at the start and at the result.
json validationJson(const std::string& file, double initial, double final) {
  return {{"file", file}, {"initial_gc_error", initial}, {"final_gc_error", final}};
}
}  // namespace

json searchJson(const SearchOutcome& o) {
  const ParameterSpace& space = *o.space;
  const SearchResult& result = o.result;
  json report = {{"schema_version", kSearchDocument.schema_version},
                 {"kind", kSearchDocument.kind},
                 {"method", methodName(o.method)},
                 {"robot", o.robot},
                 {"settings", o.settings},
                 {"termination", result.termination},
                 {"initial_gc_error", result.initial_gc},
                 {"final_gc_error", result.best_gc},
                 {"estimate", estimateJson(space, result.best_x)},
                 {"initial_estimate", estimateJson(space, space.project(space.initial()))},
                 {"history", historyJson(result.history)},
                 {"evaluations", result.evaluations},
                 {"seconds", result.seconds}};
  if (o.initial_parameter_error) {
    report["initial_parameter_error"] = *o.initial_parameter_error;
    report["final_parameter_error"] = *o.final_parameter_error;
    json evaluated = json::array();
    for (const auto& [gc, pe] : result.evaluated) evaluated.push_back({gc, pe});
    report["evaluated"] = {{"columns", {"gc_error", "parameter_error"}}, {"rows", evaluated}};
  }
  if (!o.validate_file.empty())
    report["validation"] =
        validationJson(o.validate_file, o.validate_initial_gc, o.validate_final_gc);
  embedModel(report, o.model, o.source);  // the robot searched on (nominal parameters)
  return report;
}

std::string searchSummary(const SearchOutcome& o, const std::string& dir) {
  const SearchResult& r = o.result;
  std::ostringstream out;
  out << o.robot << " " << methodName(o.method) << ": GC error " << r.initial_gc << " -> "
      << r.best_gc << " (" << r.initial_gc / std::max(r.best_gc, 1e-300) << "x lower) in "
      << r.evaluations << " evaluations, " << r.seconds << " s (" << r.termination << ")";
  if (!o.validate_file.empty())
    out << "; held-out " << o.validate_initial_gc << " -> " << o.validate_final_gc;
  out << "\nwrote " << dir << "/search.json\n";
  return out.str();
}

std::string searchProgressLine(Method method, const SearchState& state,
                               const SearchBudget& budget) {
  if (state.history.empty()) return "";
  const HistoryEntry& h = state.history.back();
  char line[256];
  std::snprintf(line, sizeof(line), "[%s] %s %d: GC error %.4g (initial %.4g), %ld evaluations",
                methodName(method), h.stage == "ga" ? "generation" : "round", h.iteration,
                h.best_gc, state.initial_gc, h.evaluations);
  // The budget that ends first decides the share done.
  double done = -1.0;
  if (budget.max_seconds > 0.0) done = std::max(done, h.seconds / budget.max_seconds);
  if (budget.max_evaluations > 0)
    done = std::max(done, static_cast<double>(h.evaluations) / budget.max_evaluations);
  std::string text = line;
  text += done >= 0.0 ? "; " + progressText(done, h.seconds) + "   "
                      : ", " + formatNumber(h.seconds, 3) + " s   ";
  return text;
}

namespace {

json refineBaseJson(const RefineOutcome& o) {
  const RefineResult& result = o.result;
  const BaseParameters& base = o.base;
  // No uncertainty (turned off, or skipped after Ctrl-C): the estimates with null deviations.
  const bool has_uncertainty = result.beta_std_dev.size() == base.numBase();
  json values = json::array();
  for (int j = 0; j < base.numBase(); ++j) {
    const double sd = has_uncertainty ? result.beta_std_dev[j] : NAN;
    values.push_back(
        {{"name", base.baseName(j)},
         {"expression", base.expression(j)},
         {"initial", o.beta0[j]},
         {"estimate", result.beta[j]},
         {"base_stage_estimate", numberOrNull(result.base_stage ? result.base_beta[j] : NAN)},
         {"std_dev", numberOrNull(sd)},
         {"confidence_95",
          has_uncertainty ? json{result.beta[j] - 1.96 * sd, result.beta[j] + 1.96 * sd} : json()},
         {"relative_std_dev_percent",
          numberOrNull(result.beta[j] != 0.0 ? 100.0 * sd / std::abs(result.beta[j]) : INFINITY)}});
  }
  json covariance = has_uncertainty ? json::array() : json();
  for (int j = 0; has_uncertainty && j < base.numBase(); ++j)
    covariance.push_back(std::vector<double>(result.beta_covariance.row(j).begin(),
                                             result.beta_covariance.row(j).end()));
  return {{"values", values},
          {"covariance", covariance},
          {"residual_variance", result.sigma2},
          {"degrees_of_freedom", result.degrees_of_freedom},
          {"information_rank", result.information_rank},
          {"note", has_uncertainty
                       ? "covariance in base coordinates: sigma^2 (J_beta^T J_beta)^-1, the "
                         "segment starts eliminated when estimated"
                   : !result.uncertainty_skipped.empty()
                       ? "no covariance: " + result.uncertainty_skipped
                       : std::string("no covariance: the uncertainty pass did not run "
                                     "(interrupted, or turned off)")}};
}

}  // namespace

json refineJson(const RefineOutcome& o) {
  const RefineResult& result = o.result;
  const ParameterSpace& space = *o.space;
  const RefineOptions& options = o.options;
  json history = json::array();
  for (const RefineIteration& h : result.history)
    history.push_back({{"stage", h.stage},
                       {"iteration", h.iteration},
                       {"cost", h.cost},
                       {"gradient_max_norm", h.gradient_max_norm},
                       {"seconds", h.seconds}});
  json free_directions = json::array();
  for (const FreeDirection& d : result.free_directions) {
    json combination = json::object();
    for (const auto& [name, coefficient] : d.combination) combination[name] = coefficient;
    free_directions.push_back(combination);
  }
  json report = {
      {"schema_version", kRefineDocument.schema_version},
      {"kind", kRefineDocument.kind},
      {"robot", o.robot},
      {"from", {{"file", o.from_file}, {"kind", o.from_kind}}},
      {"data", o.data_file},
      {"settings",
       {{"form", parameterFormName(space.options().form)},
        {"free_parameters", space.freeNames()},
        {"range", space.options().relative_range},
        {"mass_constraint", space.options().total_mass_constraint},
        {"total_mass", space.options().total_mass},
        {"horizon", o.segment_options.horizon},
        {"segments", o.num_segments},
        {"estimate_initial_states", options.estimate_initial_states},
        {"continuity_weight", options.continuity_weight},
        {"chained_segments", result.chained_segments},
        {"gauge", options.fix_gauge},
        {"base_stage", options.base_stage},
        {"max_iterations", options.max_iterations},
        {"linear_solver", result.linear_solver}}},
      {"base_stage",
       {{"run", result.base_stage},
        {"gc_error", result.base_gc},
        {"iterations", result.base_iterations},
        {"termination", result.base_termination},
        {"map_back_error", result.map_back_error},
        {"map_back_used", result.map_back_used},
        {"note",
         "solved in base coordinates first, then the free parameters fitted to that beta within "
         "their bounds (map_back_error: RMS relative difference), then polished"}}},
      {"termination", result.termination},
      {"solution_usable", result.usable},
      {"interrupted", result.interrupted},
      {"iterations", result.iterations},
      {"seconds", result.seconds},
      {"initial_gc_error", result.initial_gc},
      {"final_gc_error", result.final_gc},
      {"cost_history", history},
      {"estimate", estimateJson(space, result.x)},
      {"initial_estimate", estimateJson(space, o.x0)},
      {"parameters_at_bound", result.at_bound},
      {"base_parameters", refineBaseJson(o)},
      {"identifiability",
       {{"free_parameters", space.numFree()},
        {"base_directions_reachable", result.free_parameter_rank},
        {"gauge_dimension", result.gauge_dimension},
        {"free_directions", free_directions},
        {"note",
         "each free direction is a combination of free parameters that leaves every base "
         "parameter unchanged: the GC error cannot determine it"}}}};
  if (o.rms_start_shift)
    report["initial_states"] = {{"rms_shift_from_measured", *o.rms_start_shift}};
  if (o.has_truth) {
    report["initial_parameter_error"] = o.initial_parameter_error;
    report["final_parameter_error"] = o.final_parameter_error;
    report["initial_base_parameter_error"] = o.initial_base_error;
    report["final_base_parameter_error"] = o.final_base_error;
    report["final_base_parameter_error_max"] = o.final_base_error_max;
    if (o.base_stage_base_error)
      report["base_stage"]["base_parameter_error"] = *o.base_stage_base_error;
  }
  if (!o.validate_file.empty())
    report["validation"] =
        validationJson(o.validate_file, o.validate_initial_gc, o.validate_final_gc);
  embedModel(report, o.model, o.source);  // the robot refined on (nominal parameters)
  return report;
}

std::string refineSummary(const RefineOutcome& o, const std::string& dir) {
  const RefineResult& r = o.result;
  std::ostringstream out;
  out << o.robot << " refine: GC error " << r.initial_gc << " -> " << r.final_gc << " in ";
  if (r.base_stage)
    out << r.base_iterations << " + " << r.iterations
        << " iterations (base coordinates + parameters), ";
  else
    out << r.iterations << " iterations, ";
  out << r.seconds << " s (" << r.termination.substr(0, r.termination.find(':')) << ")";
  if (o.has_truth)
    out << "; base-parameter error " << o.initial_base_error << " -> " << o.final_base_error;
  if (!r.uncertainty_skipped.empty()) out << "\nno uncertainty: " << r.uncertainty_skipped;
  out << "\nwrote " << dir << "/refine.json\n";
  return out.str();
}

}  // namespace dynid

namespace dynid {

std::string refineWarning(const RefineOutcome& o) {
  const std::string& t = o.result.termination;
  if (t.rfind("CONVERGENCE", 0) == 0 || o.result.interrupted) return "";
  return "the refinement stopped before converging (" + t.substr(0, t.find(':')) + " after " +
         std::to_string(o.result.iterations) +
         " iterations): raise --max-iterations or --budget-seconds to go on";
}

}  // namespace dynid
