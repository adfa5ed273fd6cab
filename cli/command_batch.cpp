// dynid batch: a grid of study runs (analysis/study.hpp) in parallel worker processes, resumable,
// sharded for cluster schedulers, with one results table. See docs/BATCH.md.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "analysis/study.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/io.hpp"
#include "reports/metrics_json.hpp"

extern char** environ;

namespace dynid::cli {

namespace {

using nlohmann::json;

std::atomic<bool> interrupted{false};
extern "C" void onBatchInterrupt(int) { interrupted.store(true); }

/// Calls f(name, member) for every StudySettings field a run's spec sets, in the table's column
/// order: the one list behind the spec's defaults, its columns and settingsOf. (threads is not a
/// spec field: batch parallelism is across runs, --jobs.)
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
}

/// The keys a run's spec has, with their defaults (StudySettings).
const json& specDefaults() {
  static const json defaults = [] {
    json out{{"method", nullptr}};
    const StudySettings s;
    forEachSpecField(s, [&](const char* key, const auto& value) { out[key] = value; });
    return out;
  }();
  return defaults;
}
/// The results table's spec columns: the method, then the settings.
const std::vector<std::string> kColumns = [] {
  std::vector<std::string> out{"method"};
  const StudySettings s;
  forEachSpecField(s, [&](const char* key, const auto&) { out.emplace_back(key); });
  return out;
}();
const std::vector<std::string> kMetrics = {"gc_error_initial", "gc_error_train", "gc_error_test",
                                           "torque_rms_test",  "param_error",    "base_param_error",
                                           "evaluations",      "seconds"};

/// Checks one spec value's type against its default; `where` names it in errors.
void checkValue(const std::string& key, const json& value, const std::string& file,
                const std::string& where) {
  const json& d = specDefaults().at(key);
  const bool ok = key == "method" || key == "robot" ? value.is_string()
                  : key == "seed"                   ? value.is_number_unsigned()
                  : d.is_number_integer()           ? value.is_number_integer()
                                                    : value.is_number();
  if (!ok) throw ParseError(file, 0, where, "has the wrong type: " + value.dump());
  if (key == "method") {
    const auto& m = studyMethods();
    if (std::find(m.begin(), m.end(), value.get<std::string>()) == m.end())
      throw ParseError(file, 0, where,
                       "unknown method " + value.dump() +
                           " (ols, wls, pc, nlo, ga, hybrid, nlo_refined, ga_refined or "
                           "hybrid_refined)");
  }
}

/// Every run of the manifest, in grid order (keys sorted, the last varying fastest).
std::vector<json> expandManifest(const std::string& file) {
  json manifest;
  try {
    manifest = json::parse(readFile(file));
  } catch (const json::parse_error& e) {
    throw ParseError(file, 0, "", std::string("invalid JSON: ") + e.what());
  }
  if (!manifest.is_object() || manifest.value("schema_version", 0) != 1)
    throw ParseError(file, 0, "schema_version", "must be 1");
  for (const auto& [key, value] : manifest.items())
    if (key != "schema_version" && key != "grid" && key != "fixed" && key != "description")
      throw ParseError(file, 0, key, "unknown key (schema_version, description, grid, fixed)");
  json base = specDefaults();
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
    if (runs.size() > 1000000) throw ParseError(file, 0, "grid", "expands to over 1e6 runs");
  }
  if (runs.front()["method"].is_null())
    throw ParseError(file, 0, "method", "missing: give it in grid or fixed");
  return runs;
}

/// FNV-1a of the spec's JSON text, as 16 hex digits: the run's identity.
std::string specHash(const json& spec) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : spec.dump()) h = (h ^ c) * 1099511628211ULL;
  char buffer[17];
  std::snprintf(buffer, sizeof(buffer), "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

std::string runName(std::size_t index, const json& spec) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%06zu", index);
  return std::string(buffer) + "-" + specHash(spec);
}

/// The stored result of a run when it is complete and for this very spec, else null.
json storedResult(const std::string& path, const json& spec) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return nullptr;
  try {
    json r = json::parse(readFile(path));
    if (r.value("kind", "") == "dynid.batch.run" && r["spec"] == spec && r["metrics"].is_object())
      return r;
  } catch (const std::exception&) {
  }
  return nullptr;
}

StudySettings settingsOf(const json& spec) {
  StudySettings s;
  forEachSpecField(s, [&](const char* key, auto& value) {
    value = spec.at(key).get<std::decay_t<decltype(value)>>();
  });
  s.threads = 1;  // batch parallelism is across runs (--jobs)
  return s;
}

/// Writes results.json and results.csv for the runs found (in index order).
void writeTables(const std::string& dir, const std::vector<std::pair<std::string, json>>& done,
                 std::size_t total, const std::vector<std::string>& missing) {
  json rows = json::array();
  std::ostringstream csv;
  csv << "run";
  for (const std::string& c : kColumns) csv << "," << c;
  for (const std::string& m : kMetrics) csv << "," << m;
  csv << "\n";
  for (const auto& [name, result] : done) {
    json row = {{"run", name}};
    csv << name;
    for (const std::string& c : kColumns) {
      row[c] = result["spec"][c];
      csv << ","
          << (result["spec"][c].is_string() ? result["spec"][c].get<std::string>()
                                            : result["spec"][c].dump());
    }
    for (const std::string& m : kMetrics) {
      row[m] = result["metrics"][m];
      csv << "," << (result["metrics"][m].is_null() ? "" : result["metrics"][m].dump());
    }
    csv << "\n";
    rows.push_back(row);
  }
  const json table = {{"schema_version", 1}, {"kind", "dynid.batch.results"},
                      {"runs_total", total}, {"runs_done", done.size()},
                      {"missing", missing},  {"rows", rows}};
  writeFileAtomically(dir + "/results.json", table.dump(1) + "\n");
  writeFileAtomically(dir + "/results.csv", csv.str());
}

/// This executable's path, to start the workers.
std::string selfPath() {
  std::error_code ec;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw InputError("cannot find the dynid executable (/proc/self/exe)");
  return path.string();
}

int runOne(const std::vector<std::string>& args) {
  po::options_description options("dynid batch run");
  options.add_options()("spec", po::value<std::string>()->required(), "the run's spec (JSON)")(
      "out", po::value<std::string>()->required(), "result file");
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid batch run --spec JSON --out FILE (batch's worker)",
                        vm))
    return kExitOk;
  json spec;
  try {
    spec = json::parse(vm["spec"].as<std::string>());
  } catch (const json::parse_error& e) {
    throw UsageError(std::string("--spec is not JSON: ") + e.what());
  }
  for (const auto& [key, value] : specDefaults().items())
    if (!spec.contains(key)) throw UsageError("--spec lacks '" + key + "'");
  Study study(settingsOf(spec));
  const MethodMetrics m = study.run(spec["method"]);
  const json result = {{"schema_version", 1},
                       {"kind", "dynid.batch.run"},
                       {"spec", spec},
                       {"metrics", metricsJson(m)}};
  writeFileAtomically(vm["out"].as<std::string>(), result.dump(1) + "\n");
  return kExitOk;
}

/// Reads every run result under dir/runs: (name, result).
std::map<std::string, json> readRuns(const std::string& dir) {
  std::map<std::string, json> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/runs", ec)) {
    if (entry.path().extension() != ".json") continue;
    try {
      json r = json::parse(readFile(entry.path().string()));
      if (r.value("kind", "") == "dynid.batch.run") out[entry.path().stem().string()] = r;
    } catch (const std::exception&) {
    }
  }
  if (ec) throw InputError(dir + "/runs: " + ec.message());
  return out;
}

int runMerge(const std::vector<std::string>& args) {
  po::options_description options("dynid batch merge");
  options.add_options()("dirs", po::value<std::vector<std::string>>()->multitoken()->required(),
                        "shard output directories")("out", po::value<std::string>()->required(),
                                                    "merged output directory");
  po::positional_options_description positional;
  positional.add("dirs", -1);
  po::variables_map vm;
  const std::string usage = "dynid batch merge DIR... --out DIR";
  if (std::find(args.begin(), args.end(), "--help") != args.end() ||
      std::find(args.begin(), args.end(), "-h") != args.end()) {
    std::cout << "usage: " << usage << "\n\n" << options;
    return kExitOk;
  }
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(std::string(e.what()) + "\nusage: " + usage);
  }
  const std::string out = vm["out"].as<std::string>();
  std::map<std::string, json> merged;
  std::size_t total = 0;
  for (const std::string& dir : vm["dirs"].as<std::vector<std::string>>()) {
    const json table = [&] {
      try {
        return json::parse(readFile(dir + "/results.json"));
      } catch (const json::parse_error& e) {
        throw ParseError(dir + "/results.json", 0, "", std::string("invalid JSON: ") + e.what());
      }
    }();
    total = std::max<std::size_t>(total, table.value("runs_total", 0));
    for (auto& [name, result] : readRuns(dir)) {
      const auto [it, inserted] = merged.emplace(name, result);
      if (!inserted && it->second["spec"] != result["spec"])
        throw InputError("run " + name + " differs between the shards (" + dir + ")");
    }
  }
  std::filesystem::create_directories(out + "/runs");
  std::vector<std::pair<std::string, json>> done(merged.begin(), merged.end());
  for (const auto& [name, result] : done)
    writeFileAtomically(out + "/runs/" + name + ".json", result.dump(1) + "\n");
  writeTables(out, done, total, {});
  std::cout << "merged " << done.size() << " of " << total << " runs into " << out
            << "/results.csv and results.json\n";
  return kExitOk;
}

}  // namespace

int runBatch(const std::vector<std::string>& args) {
  if (!args.empty() && args[0] == "run") return runOne({args.begin() + 1, args.end()});
  if (!args.empty() && args[0] == "merge") return runMerge({args.begin() + 1, args.end()});
  po::options_description options("dynid batch");
  options.add_options()("manifest", po::value<std::string>()->required(), "MANIFEST.json")(
      "jobs", po::value<int>()->default_value(1), "runs at a time (worker processes)")(
      "shard", po::value<std::string>(), "K/N: only the runs whose index mod N is K - 1")(
      "quick", po::bool_switch(),
      "every run with 4 s of data, 20 segments, 100-evaluation searches, 20 refinement "
      "iterations (tests, trials)")("out", po::value<std::string>()->required(),
                                    "output directory");
  po::positional_options_description positional;
  positional.add("manifest", 1);
  const std::string usage =
      "dynid batch MANIFEST.json --jobs N [--shard K/N] [--quick] --out DIR\n"
      "       dynid batch merge DIR... --out DIR";
  if (std::find(args.begin(), args.end(), "--help") != args.end() ||
      std::find(args.begin(), args.end(), "-h") != args.end()) {
    std::cout << "usage: " << usage << "\n\n" << options;
    return kExitOk;
  }
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(std::string(e.what()) + "\nusage: " + usage);
  }
  const int jobs = vm["jobs"].as<int>();
  if (jobs < 1) throw UsageError("--jobs must be >= 1");
  int shard = 1, shards = 1;
  if (vm.count("shard")) {
    const std::string s = vm["shard"].as<std::string>();
    char slash = 0;
    std::istringstream in(s);
    if (!(in >> shard >> slash >> shards) || slash != '/' || !in.eof() || shards < 1 || shard < 1 ||
        shard > shards)
      throw UsageError("--shard must be K/N with 1 <= K <= N, not '" + s + "'");
  }
  const std::string manifest = vm["manifest"].as<std::string>();
  const std::string dir = vm["out"].as<std::string>();
  std::vector<json> runs = expandManifest(manifest);
  if (vm["quick"].as<bool>())
    for (json& run : runs) {
      run["train_seconds"] = 4.0;
      run["test_seconds"] = 4.0;
      run["segments"] = 20;
      run["search_seconds"] = 0.0;
      run["search_evaluations"] = 100;
      run["refine_iterations"] = 20;
    }
  // Every run's values checked before anything starts (a bad one would only fail in its worker).
  for (std::size_t i = 0; i < runs.size(); ++i) {
    try {
      validateStudySettings(settingsOf(runs[i]));
    } catch (const InputError& e) {
      throw ParseError(manifest, 0, "run " + std::to_string(i), e.what());
    }
  }
  std::filesystem::create_directories(dir + "/runs");

  // This shard's runs; those with a valid stored result are skipped.
  std::vector<std::size_t> mine, todo;
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(shards)) == shard - 1) mine.push_back(i);
  const auto path = [&](std::size_t i) { return dir + "/runs/" + runName(i, runs[i]) + ".json"; };
  for (std::size_t i : mine)
    if (storedResult(path(i), runs[i]).is_null()) todo.push_back(i);
  std::cerr << "dynid batch: " << runs.size() << " runs in the grid, " << mine.size()
            << " in this shard, " << mine.size() - todo.size() << " already done\n";

  // Worker processes, `jobs` at a time.
  const std::string self = selfPath();
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  interrupted.store(false);
  auto previous = std::signal(SIGINT, onBatchInterrupt);
  std::map<pid_t, std::size_t> running;
  std::vector<std::string> failed;
  std::size_t next = 0, finished = 0;
  while ((next < todo.size() && !interrupted.load()) || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < jobs && !interrupted.load()) {
      const std::size_t i = todo[next++];
      const std::vector<std::string> argv_strings = {self,           "batch", "run",  "--spec",
                                                     runs[i].dump(), "--out", path(i)};
      std::vector<char*> argv;
      for (const std::string& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      pid_t pid = 0;
      if (posix_spawn(&pid, self.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
        failed.push_back(runName(i, runs[i]) + " (could not start a worker)");
        continue;
      }
      running[pid] = i;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t i = it->second;
    running.erase(it);
    ++finished;
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0) && !interrupted.load())
      failed.push_back(runName(i, runs[i]));
    if (terminal)
      std::cerr << "\r[batch] " << finished << "/" << todo.size() << " runs finished" << std::flush;
  }
  std::signal(SIGINT, previous);
  if (terminal) std::cerr << "\n";

  std::vector<std::pair<std::string, json>> done;
  std::vector<std::string> missing;
  for (std::size_t i : mine) {
    json r = storedResult(path(i), runs[i]);
    if (r.is_null())
      missing.push_back(runName(i, runs[i]));
    else
      done.emplace_back(runName(i, runs[i]), std::move(r));
  }
  writeTables(dir, done, runs.size(), missing);
  std::cout << "dynid batch: " << done.size() << " of " << mine.size() << " runs done; wrote "
            << dir << "/results.csv and results.json\n";
  if (interrupted.load()) {
    std::cerr << "dynid batch: interrupted; run the same command again to finish the "
              << missing.size() << " missing runs\n";
    return kExitError;
  }
  if (!failed.empty()) {
    std::cerr << "dynid batch: " << failed.size() << " runs failed:";
    for (const std::string& f : failed) std::cerr << " " << f;
    std::cerr << "\n";
    return kExitError;
  }
  return kExitOk;
}

}  // namespace dynid::cli
