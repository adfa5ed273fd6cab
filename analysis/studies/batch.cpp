#include "analysis/studies/batch.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>

#include "analysis/excitation/excite.hpp"
#include "analysis/records/document.hpp"
#include "analysis/records/excitation_record.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"
#include "data/robots.hpp"

namespace dynid {

using nlohmann::json;

namespace {

/// Calls f(name, member) for every StudySettings field a run's spec sets, in the table's column
/// order: the one list behind the spec's defaults, its columns and studySettingsOf. (threads is not
/// a spec field: batch parallelism is across runs, --jobs.)
template <typename Settings, typename F>
void forEachSpecField(Settings& s, F&& f) {
  f("robot", s.robot);
  f("seed", s.seed);
  f("noise_q", s.noise_q);
  f("noise_dq", s.noise_dq);
  f("noise_tau", s.noise_tau);
  f("train_seconds", s.train_seconds);
  f("test_seconds", s.test_seconds);
  f("segments", s.segments);
  f("horizon", s.horizon);
  f("perturb", s.perturb);
  f("search_seconds", s.search_seconds);
  f("search_evaluations", s.search_evaluations);
  f("refine_iterations", s.refine_iterations);
  f("trajectory", s.trajectory);
  f("refine_seconds", s.refine_seconds);
  f("keep_if_better", s.keep_if_better);
  f("prior_weight", s.prior_weight);
}

/// The range of each integer spec value (the StudySettings field's own limits).
std::pair<long long, long long> integerRange(const std::string& key) {
  if (key == "segments") return {0, 1000000};
  if (key == "refine_iterations") return {1, 1000000};
  return {0, 1000000000000LL};  // search_evaluations
}

/// Checks one spec value's type and, for integers, its range against the field; `where` names it
/// in errors. A robot is loaded once here, so a missing or malformed model fails before any run.
void checkValue(const std::string& key, const json& value, const std::string& file,
                const std::string& where) {
  const json& d = batchSpecDefaults().at(key);
  const bool ok = key == "method" || key == "robot" || key == "trajectory" ? value.is_string()
                  : key == "seed"         ? value.is_number_unsigned()
                  : d.is_boolean()        ? value.is_boolean()
                  : d.is_number_integer() ? value.is_number_integer()
                                          : value.is_number();
  if (!ok) throw ParseError(file, 0, where, "has the wrong type: " + value.dump());
  if (d.is_number_integer() && key != "seed") {
    const auto [lo, hi] = integerRange(key);
    JsonReader(file).integer(value, where, lo, hi);
  }
  try {
    if (key == "method") parseMethod(value.get<std::string>());
    if (key == "robot") loadRobot(value.get<std::string>());
    if (key == "trajectory" && !value.get<std::string>().empty()) {  // read once, any joint count
      readExcitationDesign(value.get<std::string>(), 0);
    }
  } catch (const Error& e) {
    throw ParseError(file, 0, where, e.what());
  }
}

/// FNV-1a of the spec's JSON text, as 16 hex digits: the run's identity.
std::string specHash(const json& spec) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : spec.dump()) h = (h ^ c) * 1099511628211ULL;
  char buffer[17];
  std::snprintf(buffer, sizeof(buffer), "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

/// --quick: every run short (tests, trials).
constexpr double kQuickSeconds = 4.0;
constexpr int kQuickSegments = 10, kQuickEvaluations = 50, kQuickRefineIterations = 5;

void applyQuick(std::vector<json>& runs) {
  for (json& run : runs) {
    run["train_seconds"] = kQuickSeconds;
    run["test_seconds"] = kQuickSeconds;
    run["segments"] = kQuickSegments;
    run["search_seconds"] = 0.0;
    run["search_evaluations"] = kQuickEvaluations;
    run["refine_iterations"] = kQuickRefineIterations;
  }
}

}  // namespace

std::string batchQuickDescription() {
  return formatNumber(kQuickSeconds, 6) + " s of data, " + std::to_string(kQuickSegments) +
         " segments, " + std::to_string(kQuickEvaluations) + "-evaluation searches, " +
         std::to_string(kQuickRefineIterations) + " refinement iterations";
}

const json& batchSpecDefaults() {
  static const json defaults = [] {
    json out{{"method", nullptr}};
    const StudySettings s;
    forEachSpecField(s, [&](const char* key, const auto& value) { out[key] = value; });
    return out;
  }();
  return defaults;
}

const std::vector<std::string>& batchSpecColumns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> out{"method"};
    const StudySettings s;
    forEachSpecField(s, [&](const char* key, const auto&) { out.emplace_back(key); });
    return out;
  }();
  return columns;
}

const std::vector<std::string>& batchMetricColumns() {
  static const std::vector<std::string> metrics = {
      "gc_error_initial", "gc_error_train",   "gc_error_test", "torque_rms_test",
      "param_error",      "base_param_error", "evaluations",   "seconds"};
  return metrics;
}

json readManifest(const std::string& file) {
  json manifest = parseJson(readFile(file), file);
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  if (dir.empty() || !manifest.is_object()) return manifest;
  const auto names_file = [](const std::string& key, const std::string& value) {
    if (value.empty() || std::filesystem::path(value).is_absolute()) return false;
    if (key == "trajectory") return true;
    const std::string ext = std::filesystem::path(value).extension().string();
    return key == "robot" && (ext == ".urdf" || ext == ".json");
  };
  const auto resolve = [&](const std::string& key, json& value) {
    if (value.is_string() && names_file(key, value.get<std::string>()))
      value = (dir / value.get<std::string>()).lexically_normal().string();
  };
  for (const char* section : {"fixed", "grid"}) {
    if (!manifest.contains(section) || !manifest[section].is_object()) continue;
    for (const char* key : {"trajectory", "robot"}) {
      if (!manifest[section].contains(key)) continue;
      json& value = manifest[section][key];
      if (value.is_array())
        for (json& v : value) resolve(key, v);
      else
        resolve(key, value);
    }
  }
  return manifest;
}

std::vector<json> expandManifest(const std::string& file) {
  return expandManifest(readManifest(file), file);
}

std::vector<json> expandManifest(const json& manifest, const std::string& file) {
  if (!manifest.is_object() || !manifest.contains("schema_version") ||
      !manifest["schema_version"].is_number_integer() || manifest["schema_version"] != 1)
    throw ParseError(file, 0, "schema_version", "must be 1");
  for (const auto& [key, value] : manifest.items())
    if (key != "schema_version" && key != "grid" && key != "fixed" && key != "description")
      throw ParseError(file, 0, key, "unknown key (schema_version, description, grid, fixed)");
  json base = batchSpecDefaults();
  const json fixed = manifest.value("fixed", json::object());
  const json grid = manifest.value("grid", json::object());
  if (!fixed.is_object()) throw ParseError(file, 0, "fixed", "must be an object");
  if (!grid.is_object()) throw ParseError(file, 0, "grid", "must be an object");
  for (const auto& [key, value] : fixed.items()) {
    if (!base.contains(key)) throw ParseError(file, 0, "fixed." + key, "unknown parameter");
    if (grid.contains(key)) throw ParseError(file, 0, "fixed." + key, "is also in grid");
    checkValue(key, value, file, "fixed." + key);
    base[key] = value;
  }
  // The grid's size before expanding it: a small manifest can describe 1e9 runs.
  double product = 1.0;
  for (const auto& [key, values] : grid.items())
    if (values.is_array()) product *= static_cast<double>(std::max<std::size_t>(values.size(), 1));
  if (product > kMaxBatchRuns)
    throw ParseError(file, 0, "grid",
                     "expands to " + formatNumber(product) +
                         " runs (at most 1e5 in one manifest: split it into several)");
  std::vector<json> runs = {base};
  for (const auto& [key, values] : grid.items()) {
    if (!base.contains(key)) throw ParseError(file, 0, "grid." + key, "unknown parameter");
    if (!values.is_array() || values.empty())
      throw ParseError(file, 0, "grid." + key, "must be a non-empty array");
    std::vector<json> next;
    for (const json& run : runs)
      for (std::size_t i = 0; i < values.size(); ++i) {
        checkValue(key, values[i], file, "grid." + key + "[" + std::to_string(i) + "]");
        json r = run;
        r[key] = values[i];
        next.push_back(r);
      }
    runs = std::move(next);
    if (static_cast<double>(runs.size()) > kMaxBatchRuns)
      throw ParseError(file, 0, "grid", "expands to over 1e5 runs");
  }
  if (runs.front()["method"].is_null())
    throw ParseError(file, 0, "method", "missing: give it in grid or fixed");
  return runs;
}

StudySettings studySettingsOf(const json& spec) {
  StudySettings s;
  forEachSpecField(s, [&](const char* key, auto& value) {
    value = spec.at(key).get<std::decay_t<decltype(value)>>();
  });
  s.threads = 1;  // batch parallelism is across runs (--jobs)
  return s;
}

std::string batchRunName(std::size_t index, const json& spec) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%06zu", index);
  return std::string(buffer) + "-" + specHash(spec);
}

BatchRunRecord runBatchSpec(const json& spec) {
  for (const auto& [key, value] : batchSpecDefaults().items())
    if (!spec.contains(key)) throw InputError("the run's spec lacks '" + key + "'");
  Study study(studySettingsOf(spec));
  const MethodMetrics m = study.run(parseMethod(spec.at("method").get<std::string>()));
  return {spec, metricsJson(m)};
}

std::string BatchPlan::path(std::size_t i) const {
  return dir + "/runs/" + batchRunName(i, runs[i]) + ".json";
}

BatchPlan planBatch(const std::string& manifest, const std::string& dir, bool quick, int shard,
                    int shards) {
  const json document = readManifest(manifest);
  BatchPlan plan{manifest, dir, expandManifest(document, manifest), {}, {}, {}};
  plan.record = BatchPlanRecord{document, quick, shard, shards}.json();
  if (quick) applyQuick(plan.runs);
  // Every run's values checked before anything starts (a bad one would only fail in its worker).
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    try {
      studySettingsOf(plan.runs[i]).check();
    } catch (const InputError& e) {
      throw ParseError(manifest, 0, "run " + std::to_string(i), e.what());
    }
  }
  // This shard's runs; those with a valid stored result are skipped.
  for (std::size_t i = 0; i < plan.runs.size(); ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(shards)) == shard - 1) plan.mine.push_back(i);
  for (std::size_t i : plan.mine)
    if (!storedBatchRun(plan.path(i), plan.runs[i])) plan.todo.push_back(i);
  return plan;
}

BatchOutcome collectBatch(const BatchPlan& plan) {
  BatchOutcome out;
  out.total = plan.runs.size();
  out.plan = plan.record;
  for (std::size_t i : plan.mine) {
    std::optional<BatchRunRecord> r = storedBatchRun(plan.path(i), plan.runs[i]);
    if (!r)
      out.missing.push_back(batchRunName(i, plan.runs[i]));
    else
      out.done.emplace_back(batchRunName(i, plan.runs[i]), std::move(*r));
  }
  return out;
}

BatchOutcome mergeBatches(const std::vector<std::string>& dirs, bool allow_missing) {
  // Every shard's plan (results.json) must be of the same manifest and settings.
  std::optional<BatchPlanRecord> reference;
  std::string reference_file;
  std::vector<bool> shard_given;
  for (const std::string& dir : dirs) {
    const std::string file = dir + "/results.json";
    const BatchPlanRecord plan = readBatchPlan(file);
    if (!reference) {
      reference = plan;
      reference_file = file;
      shard_given.assign(static_cast<std::size_t>(plan.shards), false);
    } else if (plan.manifest != reference->manifest || plan.quick != reference->quick ||
               plan.shards != reference->shards) {
      throw ParseError(file, 0, "plan",
                       "another manifest, `quick` or shard count than " + reference_file +
                           ": these are not shards of one batch");
    }
    shard_given[static_cast<std::size_t>(plan.shard - 1)] = true;
  }
  if (!reference) throw InputError("batch merge: no shard directories given");
  std::vector<json> runs = expandManifest(reference->manifest, reference_file + " (plan)");
  if (reference->quick) applyQuick(runs);
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < runs.size(); ++i) index[batchRunName(i, runs[i])] = i;

  std::map<std::string, BatchRunRecord> merged;
  for (const std::string& dir : dirs)
    for (auto& [name, result] : readBatchRuns(dir)) {
      const std::string file = dir + "/runs/" + name + ".json";
      const auto at = index.find(name);
      if (at == index.end() || result.spec != runs[at->second])
        throw ParseError(file, 0, "spec", "not a run of this batch's manifest");
      merged.emplace(name, result);  // a run in two shards: the same spec, either will do
    }
  BatchOutcome out;
  out.total = runs.size();
  BatchPlanRecord whole = *reference;
  whole.shard = whole.shards = 1;
  out.plan = whole.json();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string name = batchRunName(i, runs[i]);
    const auto it = merged.find(name);
    if (it == merged.end())
      out.missing.push_back(name);
    else
      out.done.emplace_back(name, it->second);
  }
  if (!out.missing.empty() && !allow_missing) {
    std::string absent;
    for (std::size_t k = 0; k < shard_given.size(); ++k)
      if (!shard_given[k])
        absent += (absent.empty() ? "" : ", ") + std::to_string(k + 1) + "/" +
                  std::to_string(shard_given.size());
    throw InputError("the merge is incomplete: " + std::to_string(out.missing.size()) + " of " +
                     std::to_string(runs.size()) +
                     " runs are missing (first: " + out.missing.front() + ")" +
                     (absent.empty() ? "" : "; shards not given: " + absent) +
                     ". Finish them (run each shard's command again) or pass `allow_missing`");
  }
  return out;
}

}  // namespace dynid
