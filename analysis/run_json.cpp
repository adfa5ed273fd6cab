#include "analysis/run_json.hpp"

#include <algorithm>

#include "core/errors.hpp"
#include "core/integrators.hpp"
#include "core/parameters.hpp"
#include "data/json_number.hpp"

namespace dynid {

using nlohmann::json;

namespace {

json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }
Eigen::VectorXd vectorFrom(const json& j) {
  const std::vector<double> v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

std::vector<HistoryEntry> historyFrom(const json& j) {
  std::vector<HistoryEntry> out;
  for (const json& e : j) {
    HistoryEntry h;
    h.stage = e.at("stage");
    h.iteration = e.at("iteration");
    h.best_gc = e.at("best_gc_error");
    h.best_parameter_error = numberOrNan(e.at("best_parameter_error"));
    h.min_parameter_error = numberOrNan(e.at("min_parameter_error"));
    h.evaluations = e.at("evaluations");
    h.seconds = e.at("seconds");
    out.push_back(h);
  }
  return out;
}

/// A standard vector from {name: value} (every name of the layout required).
Eigen::VectorXd standardFrom(const json& values, const std::vector<std::string>& names,
                             const std::string& file, const std::string& where) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (!values.contains(names[k]) || !values[names[k]].is_number())
      throw ParseError(file, 0, where + "." + names[k],
                       "missing or not a number (does --robot/--drives match the run?)");
    theta[static_cast<Eigen::Index>(k)] = values[names[k]].get<double>();
  }
  return theta;
}

}  // namespace

json parseJson(const std::string& text, const std::string& file) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    throw ParseError(file, 0, "", std::string("invalid JSON: ") + e.what());
  }
}

json searchSettingsJson(const SearchSettingsRecord& s) {
  return {{"form", parameterFormName(s.space.form)},
          {"free_parameters", s.free_parameters},
          {"range", s.space.relative_range},
          {"absolute_range", s.space.absolute_range},
          {"mass_constraint", s.space.total_mass_constraint},
          {"total_mass", s.space.total_mass},
          {"horizon", s.segments.horizon},
          {"segments", s.segments.num_segments},
          {"random_segments", s.segments.random_starts},
          {"integrator", integratorName(s.segments.integrator)},
          {"step", s.segments.step},
          {"normalise", s.segments.normalise},
          {"seed", s.seed},
          {"budget_evaluations", s.budget.max_evaluations},
          {"budget_seconds", s.budget.max_seconds},
          {"gc_tolerance", s.budget.gc_tolerance},
          {"population", s.ga.population},
          {"elites", s.ga.elites},
          {"migration", s.ga.migration},
          {"mutation_rate", s.ga.mutation_rate},
          {"mutation_scale", s.ga.mutation_scale},
          {"evaluations_per_seed", s.nlo.evaluations_per_seed},
          {"data", s.data}};
}

json checkpointFingerprint(json settings) {
  for (const char* key : {"budget_evaluations", "budget_seconds", "gc_tolerance"})
    settings.erase(key);
  return settings;
}

json checkpointJson(const SearchState& s, const json& settings) {
  json population = json::array();
  for (const Eigen::VectorXd& x : s.population) population.push_back(vectorJson(x));
  return {{"schema_version", 1},
          {"kind", "dynid.search_checkpoint"},
          {"settings", checkpointFingerprint(settings)},
          {"method", s.method},
          {"stage", s.stage},
          {"iteration", s.iteration},
          {"rng", s.rng},
          {"best_x", vectorJson(s.best_x)},
          {"best_gc", s.best_gc},
          {"initial_gc", numberOrNull(s.initial_gc)},
          {"population", population},
          {"population_gc", s.population_gc},
          {"evaluations", s.evaluations},
          {"seconds", s.seconds},
          {"history", historyJson(s.history)}};
}

SearchState checkpointFrom(const json& j, const std::string& file) {
  try {
    SearchState s;
    s.method = j.at("method");
    s.stage = j.at("stage");
    s.iteration = j.at("iteration");
    s.rng = j.at("rng");
    s.best_x = vectorFrom(j.at("best_x"));
    s.best_gc = j.at("best_gc");
    s.initial_gc = numberOrNan(j.at("initial_gc"));
    for (const json& x : j.at("population")) s.population.push_back(vectorFrom(x));
    s.population_gc = j.at("population_gc").get<std::vector<double>>();
    s.evaluations = j.at("evaluations");
    s.seconds = j.at("seconds");
    s.history = historyFrom(j.at("history"));
    return s;
  } catch (const json::exception& e) {
    throw ParseError(file, 0, "", std::string("not a dynid search checkpoint: ") + e.what());
  }
}

json historyJson(const std::vector<HistoryEntry>& history) {
  json out = json::array();
  for (const HistoryEntry& h : history)
    out.push_back({{"stage", h.stage},
                   {"iteration", h.iteration},
                   {"best_gc_error", h.best_gc},
                   {"best_parameter_error", numberOrNull(h.best_parameter_error)},
                   {"min_parameter_error", numberOrNull(h.min_parameter_error)},
                   {"evaluations", h.evaluations},
                   {"seconds", h.seconds}});
  return out;
}

json estimateJson(const ParameterSpace& space, const Eigen::VectorXd& x) {
  const Model model = space.modelAt(x);
  json paper = json::object(), standard = json::object();
  const std::vector<std::string> paper_names = paperParameterNames(model.numJoints());
  for (int i = 0; i < model.numJoints(); ++i) {
    const auto p = standardToPaper(toStandardVector(model.inertias()[i]));
    for (int k = 0; k < 7; ++k) paper[paper_names[7 * i + k]] = p[k];
  }
  const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
  const Eigen::VectorXd theta = model.standardParameters();
  for (int k = 0; k < theta.size(); ++k) standard[names[k]] = theta[k];
  return {{"paper", paper}, {"standard", standard}};
}

RefineStart refineStartFrom(const json& start, const std::string& from, const Model& robot,
                            const SpaceOptions& space, const SegmentOptions& segments) {
  const std::vector<std::string> names = standardParameterNames(robot.parameterLayout());
  RefineStart out{"", space, segments, robot, robot};
  try {
    if (start.contains("settings") && start.contains("estimate")) {
      out.kind = "search";
      const json& s = start.at("settings");
      out.space = SpaceOptions{};
      out.space.form = parseParameterForm(s.at("form"));
      out.space.relative_range = s.at("range");
      out.space.absolute_range = s.at("absolute_range");
      out.space.total_mass_constraint = s.at("mass_constraint");
      out.space.total_mass = s.at("total_mass");
      out.segments = SegmentOptions{};
      out.segments.horizon = s.at("horizon");
      out.segments.num_segments = s.at("segments");
      out.segments.random_starts = s.at("random_segments");
      out.segments.seed = s.at("seed");
      out.segments.integrator = parseIntegrator(s.at("integrator"));
      out.segments.step = s.at("step");
      out.segments.normalise = s.at("normalise");
      out.initial.setStandardParameters(standardFrom(start.at("initial_estimate").at("standard"),
                                                     names, from, "initial_estimate.standard"));
      out.estimate.setStandardParameters(
          standardFrom(start.at("estimate").at("standard"), names, from, "estimate.standard"));
      // Free exactly what the search freed.
      const std::vector<std::string> free = s.at("free_parameters");
      const std::vector<std::string> all =
          out.space.form == ParameterForm::kPaper
              ? paperParameterNames(robot.numJoints())
              : standardParameterNames({robot.numJoints(), DriveTerms::none()});
      for (const std::string& name : all)
        if (std::find(free.begin(), free.end(), name) == free.end())
          out.space.fixed.push_back(name);
    } else if (start.contains("standard_estimate")) {
      out.kind = "estimate";
      out.initial.setStandardParameters(standardFrom(start.at("standard_estimate").at("values"),
                                                     names, from, "standard_estimate.values"));
      out.estimate = out.initial;
    } else {
      throw ParseError(from, 0, "", "neither a dynid search.json nor an identify estimate.json");
    }
  } catch (const json::exception& e) {
    throw ParseError(from, 0, "", std::string("missing or malformed field: ") + e.what());
  }
  return out;
}

json metricsJson(const MethodMetrics& m) {
  return {{"gc_error_initial", numberOrNull(m.gc_error_initial)},
          {"gc_error_train", numberOrNull(m.gc_error_train)},
          {"gc_error_test", numberOrNull(m.gc_error_test)},
          {"torque_rms_test", numberOrNull(m.torque_rms_test)},
          {"param_error", numberOrNull(m.param_error)},
          {"base_param_error", numberOrNull(m.base_param_error)},
          {"evaluations", m.evaluations},
          {"seconds", numberOrNull(m.seconds)}};
}

}  // namespace dynid
