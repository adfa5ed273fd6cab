#include "analysis/records/search_record.hpp"

#include <algorithm>
#include <filesystem>
#include <random>
#include <sstream>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "core/integrators.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"

namespace dynid {

using nlohmann::json;

namespace {
json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }
}  // namespace

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
  json out = documentHeader(kCheckpointDocument);
  out.update(json{{"settings", checkpointFingerprint(settings)},
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
                  {"history", historyJson(s.history)}});
  return out;
}

SearchState checkpointFrom(const json& j, const std::string& file, const CheckpointShape& shape) {
  const JsonReader read(file);
  read.header(j, kCheckpointDocument.schema_version, kCheckpointDocument.kind);
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

std::optional<SearchState> readCheckpoint(const std::string& path, const json& settings,
                                          const std::string& method) {
  std::error_code error;
  if (path.empty() || !std::filesystem::exists(path, error)) return std::nullopt;
  const json saved = parseJson(readFile(path), path);
  CheckpointShape shape;
  shape.method = method;
  shape.dimension = static_cast<long>(settings.at("free_parameters").size());
  shape.population = settings.at("population").get<long>();
  if (saved.is_object() && saved.contains("settings") &&
      saved["settings"] != checkpointFingerprint(settings))
    throw ParseError(path, 0, "settings",
                     "the checkpoint was written with other settings; remove it to start afresh");
  return checkpointFrom(saved, path, shape);
}

}  // namespace dynid
