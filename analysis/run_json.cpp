#include "analysis/run_json.hpp"

#include <algorithm>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/integrators.hpp"
#include "core/parameters.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"

namespace dynid {

using nlohmann::json;

namespace {

json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }
/// A standard vector from {name: value} (every name of the layout required, each a finite number
/// within +-kMaxParameterMagnitude).
Eigen::VectorXd standardFrom(const json& values, const std::vector<std::string>& names,
                             const std::string& file, const std::string& where) {
  const JsonReader read(file);
  read.object(values, where);
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string path = where + "." + names[k];
    if (!values.contains(names[k]))
      read.fail(path, "missing (does --robot/--drives match the run?)");
    theta[static_cast<Eigen::Index>(k)] =
        read.number(values[names[k]], path, -kMaxParameterMagnitude, kMaxParameterMagnitude);
  }
  return theta;
}

}  // namespace

json parseJson(const std::string& text, const std::string& file) {
  return parseJsonDocument(text, file);
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

SearchState checkpointFrom(const json& j, const std::string& file, const CheckpointShape& shape) {
  const JsonReader read(file);
  read.header(j, 1, "dynid.search_checkpoint");
  read.onlyKeys(j, "",
                {"schema_version", "kind", "settings", "method", "stage", "iteration", "rng",
                 "best_x", "best_gc", "initial_gc", "population", "population_gc", "evaluations",
                 "seconds", "history"});
  read.object(read.field(j, "", "settings"), "settings");
  constexpr long long kMaxCount = 1'000'000'000'000'000LL;  // far beyond any run's evaluations
  SearchState s;
  s.method = read.string(j, "", "method");
  if (s.method != "nlo" && s.method != "ga" && s.method != "hybrid")
    read.fail("method", "must be nlo, ga or hybrid, not \"" + s.method + "\"");
  if (!shape.method.empty() && s.method != shape.method)
    read.fail("method", "the checkpoint is of a " + s.method + " search, not " + shape.method);
  s.stage = read.string(j, "", "stage");
  if (s.stage != "nlo" && s.stage != "ga")
    read.fail("stage", "must be nlo or ga, not \"" + s.stage + "\"");
  s.iteration = static_cast<int>(read.integer(j, "", "iteration", 0, 1'000'000'000));
  s.rng = read.string(j, "", "rng");
  {
    std::istringstream in(s.rng);
    std::mt19937_64 probe;
    if (!(in >> probe) || !(in >> std::ws).eof())
      read.fail("rng", "not a std::mt19937_64 state (312 numbers and an index)");
  }
  s.best_x = read.vector(read.field(j, "", "best_x"), "best_x", shape.dimension);
  s.best_gc = read.number(j, "", "best_gc", 0.0);
  const json& initial = read.field(j, "", "initial_gc");
  s.initial_gc = initial.is_null() ? std::nan("") : read.number(initial, "initial_gc", 0.0);
  const json& population = read.array(read.field(j, "", "population"), "population");
  if (shape.population > 0 && !population.empty() &&
      static_cast<long>(population.size()) != shape.population)
    read.fail("population", "has " + std::to_string(population.size()) +
                                " members; the search's population is " +
                                std::to_string(shape.population));
  for (std::size_t i = 0; i < population.size(); ++i)
    s.population.push_back(
        read.vector(population[i], JsonReader::index("population", i), shape.dimension));
  const Eigen::VectorXd gc = read.vector(read.field(j, "", "population_gc"), "population_gc",
                                         static_cast<long>(population.size()));
  for (Eigen::Index i = 0; i < gc.size(); ++i) {
    if (gc[i] < 0.0)
      read.fail(JsonReader::index("population_gc", static_cast<std::size_t>(i)),
                "a GC error is >= 0");
    s.population_gc.push_back(gc[i]);
  }
  s.evaluations = static_cast<long>(read.integer(j, "", "evaluations", 0, kMaxCount));
  s.seconds = read.number(j, "", "seconds", 0.0, 1e12);
  const json& history = read.array(read.field(j, "", "history"), "history");
  for (std::size_t i = 0; i < history.size(); ++i) {
    const std::string path = JsonReader::index("history", i);
    const json& e = history[i];
    read.onlyKeys(e, path,
                  {"stage", "iteration", "best_gc_error", "best_parameter_error",
                   "min_parameter_error", "evaluations", "seconds"});
    HistoryEntry h;
    h.stage = read.string(e, path, "stage");
    h.iteration = static_cast<int>(read.integer(e, path, "iteration", 0, 1'000'000'000));
    h.best_gc = read.number(e, path, "best_gc_error", 0.0);
    for (auto [key, target] : {std::pair{"best_parameter_error", &h.best_parameter_error},
                               std::pair{"min_parameter_error", &h.min_parameter_error}}) {
      const json& v = read.field(e, path, key);
      *target = v.is_null() ? std::nan("") : read.number(v, JsonReader::join(path, key), 0.0);
    }
    h.evaluations = static_cast<long>(read.integer(e, path, "evaluations", 0, kMaxCount));
    h.seconds = read.number(e, path, "seconds", 0.0, 1e12);
    s.history.push_back(h);
  }
  return s;
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
      const JsonReader read(from);
      read.header(start, 1, nullptr);
      read.onlyKeys(
          start, "",
          {"schema_version", "method", "robot", "settings", "termination", "initial_gc_error",
           "final_gc_error", "estimate", "initial_estimate", "history", "evaluations", "seconds",
           "initial_parameter_error", "final_parameter_error", "evaluated", "validation"});
      const json& s = read.field(start, "", "settings");
      read.onlyKeys(s, "settings",
                    {"form",
                     "free_parameters",
                     "range",
                     "absolute_range",
                     "mass_constraint",
                     "total_mass",
                     "horizon",
                     "segments",
                     "random_segments",
                     "integrator",
                     "step",
                     "normalise",
                     "seed",
                     "budget_evaluations",
                     "budget_seconds",
                     "gc_tolerance",
                     "population",
                     "elites",
                     "migration",
                     "mutation_rate",
                     "mutation_scale",
                     "evaluations_per_seed",
                     "data"});
      const auto named = [&](const char* key, auto parse) {
        const std::string text = read.string(s, "settings", key);
        try {
          return parse(text);
        } catch (const std::exception& e) {
          read.fail(std::string("settings.") + key, e.what());
        }
      };
      out.space = SpaceOptions{};
      out.space.form = named("form", [](const std::string& t) { return parseParameterForm(t); });
      out.space.relative_range = read.number(s, "settings", "range", 0.0, 1e3);
      out.space.absolute_range = read.number(s, "settings", "absolute_range", 0.0, 1e6);
      out.space.total_mass_constraint = read.boolean(s, "settings", "mass_constraint");
      out.space.total_mass = read.number(s, "settings", "total_mass", 1e-12, 1e6);
      out.segments = SegmentOptions{};
      out.segments.horizon = read.number(s, "settings", "horizon", 1e-9, 1e4);
      out.segments.num_segments =
          static_cast<int>(read.integer(s, "settings", "segments", 0, 1000000));
      out.segments.random_starts = read.boolean(s, "settings", "random_segments");
      out.segments.seed = read.unsignedInteger(s, "settings", "seed");
      out.segments.integrator =
          named("integrator", [](const std::string& t) { return parseIntegrator(t); });
      out.segments.step = read.number(s, "settings", "step", 1e-6, 10.0);
      out.segments.normalise = read.boolean(s, "settings", "normalise");
      out.initial.setStandardParameters(standardFrom(start.at("initial_estimate").at("standard"),
                                                     names, from, "initial_estimate.standard"));
      out.estimate.setStandardParameters(
          standardFrom(start.at("estimate").at("standard"), names, from, "estimate.standard"));
      // Free exactly what the search freed.
      const std::vector<std::string> free =
          read.strings(read.field(s, "settings", "free_parameters"), "settings.free_parameters");
      const std::vector<std::string> all =
          out.space.form == ParameterForm::kPaper
              ? paperParameterNames(robot.numJoints())
              : standardParameterNames({robot.numJoints(), DriveTerms::none()});
      for (const std::string& name : all)
        if (std::find(free.begin(), free.end(), name) == free.end())
          out.space.fixed.push_back(name);
      for (const std::string& name : free)
        if (std::find(all.begin(), all.end(), name) == all.end())
          read.fail("settings.free_parameters", "'" + name + "' is not a parameter of the robot");
    } else if (start.contains("standard_estimate")) {
      out.kind = "estimate";
      out.initial.setStandardParameters(
          standardVectorFrom(estimateRecordFrom(start, from), names, from, ""));
      out.estimate = out.initial;
    } else {
      throw ParseError(from, 0, "", "neither a dynid search.json nor an identify estimate.json");
    }
  } catch (const json::exception& e) {
    throw ParseError(from, 0, "", std::string("missing or malformed field: ") + e.what());
  }
  return out;
}

EstimateRecord estimateRecordFrom(const json& document, const std::string& file) {
  const JsonReader read(file);
  read.header(document, kEstimateSchemaVersion, nullptr);
  read.onlyKeys(document, "",
                {"schema_version",
                 "robot",
                 "robot_spec",
                 "kinematics",
                 "drives",
                 "drive_terms",
                 "method",
                 "data",
                 "num_base",
                 "base_parameters",
                 "condition_number",
                 "condition_number_unscaled",
                 "joint_sigma",
                 "residual_rms",
                 "measured_rms",
                 "relative_error",
                 "joint_relative_error",
                 "standard_estimate",
                 "physically_consistent",
                 "write_back",
                 "validation"});
  EstimateRecord out;
  if (document.contains("robot_spec")) out.robot_spec = read.string(document, "", "robot_spec");
  if (document.contains("method")) out.method = read.string(document, "", "method");
  if (document.contains("drive_terms"))
    out.drive_terms = read.strings(document["drive_terms"], "drive_terms");
  const json& standard = read.field(document, "", "standard_estimate");
  read.onlyKeys(standard, "standard_estimate", {"note", "values"});
  const json& values =
      read.object(read.field(standard, "standard_estimate", "values"), "standard_estimate.values");
  for (const auto& [name, value] : values.items())
    out.standard[name] = read.number(value, "standard_estimate.values." + name,
                                     -kMaxParameterMagnitude, kMaxParameterMagnitude);
  if (document.contains("kinematics")) {
    const json& rows = read.array(document["kinematics"], "kinematics");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string path = JsonReader::index("kinematics", i);
      if (!rows[i].is_array() || rows[i].size() != 15) read.fail(path, "expected 15 numbers");
      for (std::size_t c = 0; c < 15; ++c)
        if (!rows[i][c].is_number() && !rows[i][c].is_null())
          read.fail(JsonReader::index(path, c), "expected a number");
    }
    out.kinematics = rows;
  }
  return out;
}

Eigen::VectorXd standardVectorFrom(const EstimateRecord& record,
                                   const std::vector<std::string>& names, const std::string& file,
                                   const std::string& robot_spec) {
  const std::string robot = robot_spec.empty() ? "the robot" : "robot '" + robot_spec + "'";
  Eigen::VectorXd theta(static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto it = record.standard.find(names[k]);
    if (it == record.standard.end())
      throw ParseError(file, 0, "standard_estimate.values." + names[k],
                       "missing: " + robot + " has this parameter (" +
                           std::to_string(names.size()) + " in all, the estimate " +
                           std::to_string(record.standard.size()) +
                           "): the estimate was made for another robot or drive terms, or edited");
    theta[static_cast<Eigen::Index>(k)] = it->second;
  }
  for (const auto& [name, value] : record.standard)
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw ParseError(file, 0, "standard_estimate.values." + name,
                       "is not a parameter of " + robot +
                           ": the estimate was made for another robot or drive terms");
  return theta;
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
