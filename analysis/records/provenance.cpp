#include "analysis/records/provenance.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <ctime>
#include <mutex>
#include <thread>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/digest/sha256.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/json_reader.hpp"

namespace dynid {

namespace {

using json = nlohmann::json;

/// The wall-clock fields of each kind (the searches' and solvers' own times); the rest of a
/// document is a function of its command and inputs.
struct TimeFields {
  const char* kind;
  std::vector<std::string> pointers;
};
const std::vector<TimeFields>& timeFieldTable() {
  static const std::vector<TimeFields> table = {
      {"dynid.estimate",
       {"/combined/seconds", "/combined/cost_history/*/seconds", "/front/points/*/seconds"}},
      {"dynid.search", {"/seconds", "/history/*/seconds"}},
      {"dynid.refine", {"/seconds", "/cost_history/*/seconds"}},
      {"dynid.excitation", {"/optimiser/seconds"}},
      {"dynid.study", {"/seconds", "/methods/*/seconds", "/front/points/*/seconds"}},
      {"dynid.demo", {"/seconds", "/methods/*/seconds"}},
  };
  return table;
}

/// Sets every field `pointer` names (its "*" steps through every element or member) to null.
void clearField(json& node, const std::vector<std::string>& steps, std::size_t at) {
  if (at == steps.size()) {
    node = nullptr;
    return;
  }
  const std::string& step = steps[at];
  if (step == "*") {
    if (node.is_array() || node.is_object())
      for (json& child : node) clearField(child, steps, at + 1);
    return;
  }
  if (node.is_object() && node.contains(step)) clearField(node[step], steps, at + 1);
}

void clearPointer(json& document, const std::string& pointer) {
  std::vector<std::string> steps;
  std::size_t start = 1;
  while (start <= pointer.size()) {
    const std::size_t end = std::min(pointer.find('/', start), pointer.size());
    steps.push_back(pointer.substr(start, end - start));
    start = end + 1;
  }
  clearField(document, steps, 0);
}

/// The document as the comparison sees it: its time fields and provenance times null.
json withoutTimes(json document) {
  if (!document.is_object() || !document.contains("provenance")) return document;
  json& p = document["provenance"];
  if (p.is_object()) {
    if (p.contains("time_fields") && p["time_fields"].is_array())
      for (const json& pointer : p["time_fields"])
        if (pointer.is_string()) clearPointer(document, pointer.get<std::string>());
    p["started"] = nullptr;
    p["seconds"] = nullptr;
  }
  return document;
}

/// Where `option`'s value sits in a command line: the index of the value, or npos. An
/// "OPTION=VALUE" word counts as its own value.
std::size_t valueIndex(const std::vector<std::string>& command, const std::string& option) {
  for (std::size_t i = 0; i < command.size(); ++i) {
    if (command[i] == option && i + 1 < command.size()) return i + 1;
    if (command[i].rfind(option + "=", 0) == 0) return i;
  }
  return std::string::npos;
}

/// Every difference between `a` and `b`, as "POINTER: A -> B", into `out`.
void differences(const json& a, const json& b, const std::string& at,
                 std::vector<std::string>& out) {
  if (a.type() == b.type() && (a.is_object() || a.is_array())) {
    if (a.is_object()) {
      for (auto it = a.begin(); it != a.end(); ++it)
        differences(it.value(), b.contains(it.key()) ? b[it.key()] : json(), at + "/" + it.key(),
                    out);
      for (auto it = b.begin(); it != b.end(); ++it)
        if (!a.contains(it.key())) differences(json(), it.value(), at + "/" + it.key(), out);
      return;
    }
    const std::size_t n = std::max(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i)
      differences(i < a.size() ? a[i] : json(), i < b.size() ? b[i] : json(),
                  at + "/" + std::to_string(i), out);
    return;
  }
  if (jsonText(a) == jsonText(b)) return;
  const auto shown = [](const json& v) {
    if (v.is_null()) return std::string("absent or null");
    std::string text = jsonText(v);
    return text.size() > 60 ? text.substr(0, 57) + "..." : text;
  };
  out.push_back((at.empty() ? "/" : at) + ": " + shown(a) + " -> " + shown(b));
}

// The run of this process.
std::mutex run_mutex;
std::optional<RunProvenance> current_run;
std::chrono::steady_clock::time_point run_start;

}  // namespace

std::vector<std::string> timeFieldsOf(const std::string& kind) {
  for (const TimeFields& t : timeFieldTable())
    if (kind == t.kind) return t.pointers;
  return {};
}

std::string utcTimestamp(std::chrono::system_clock::time_point when) {
  const std::time_t t = std::chrono::system_clock::to_time_t(when);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

json provenanceJson(const RunProvenance& run, const std::string& kind) {
  json inputs = json::array();
  for (const InputDigest& input : run.inputs)
    inputs.push_back(
        {{"file", input.file}, {"sha256", input.sha256.empty() ? json() : json(input.sha256)}});
  return {{"version", run.version},
          {"commit", run.commit},
          {"interface", run.interface},
          {"command", run.command},
          {"working_directory", run.working_directory},
          {"inputs", inputs},
          {"seed", run.seed ? json(*run.seed) : json()},
          {"threads", run.threads ? json(*run.threads) : json()},
          {"started", run.started},
          {"seconds", run.seconds},
          {"time_fields", timeFieldsOf(kind)}};
}

RunProvenance provenanceFrom(const json& document, const std::string& file) {
  const JsonReader read(file);
  if (!document.is_object() || !document.contains("provenance"))
    read.fail("provenance",
              "missing: the document was written by a library call, or by a dynid before 0.2.0 "
              "recorded what made its documents");
  const std::string at = "provenance";
  const json& p = read.object(document[at], at);
  read.onlyKeys(p, at,
                {"version", "commit", "interface", "command", "working_directory", "inputs", "seed",
                 "threads", "started", "seconds", "time_fields"});
  RunProvenance run;
  run.version = read.string(p, at, "version");
  run.commit = read.string(p, at, "commit");
  run.interface = read.string(p, at, "interface");
  run.command = read.strings(read.field(p, at, "command"), at + ".command");
  run.working_directory = read.string(p, at, "working_directory");
  const json& inputs = read.array(read.field(p, at, "inputs"), at + ".inputs");
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::string here = JsonReader::index(at + ".inputs", i);
    read.onlyKeys(inputs[i], here, {"file", "sha256"});
    InputDigest digest{read.string(inputs[i], here, "file"), ""};
    if (!read.field(inputs[i], here, "sha256").is_null())
      digest.sha256 = read.string(inputs[i], here, "sha256");
    run.inputs.push_back(std::move(digest));
  }
  if (!read.field(p, at, "seed").is_null()) run.seed = read.unsignedInteger(p, at, "seed");
  if (!read.field(p, at, "threads").is_null())
    run.threads = static_cast<int>(read.integer(p, at, "threads", 1, 1 << 20));
  run.started = read.string(p, at, "started");
  run.seconds = read.number(p, at, "seconds", 0.0);
  read.strings(read.field(p, at, "time_fields"), at + ".time_fields");
  return run;
}

void beginRun(RunProvenance run) {
  const std::lock_guard<std::mutex> lock(run_mutex);
  run.started = utcTimestamp(std::chrono::system_clock::now());
  run_start = std::chrono::steady_clock::now();
  current_run = std::move(run);
}

void noteRunSeed(std::uint64_t seed) {
  const std::lock_guard<std::mutex> lock(run_mutex);
  if (current_run) current_run->seed = seed;
}

void noteRunThreads(int threads) {
  const std::lock_guard<std::mutex> lock(run_mutex);
  if (current_run)
    current_run->threads =
        threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

std::optional<RunProvenance> currentRun() {
  std::optional<RunProvenance> run;
  {
    const std::lock_guard<std::mutex> lock(run_mutex);
    if (!current_run) return std::nullopt;
    run = current_run;
    run->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  }
  // Each input by content now: a regular file hashed (unless it is gone or no longer a regular
  // file), a stream recorded by name only.
  for (const CommandInput& input : commandInputs()) {
    InputDigest digest{input.path, ""};
    struct stat st {};
    if (input.regular && ::stat(input.path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
      try {
        digest.sha256 = sha256OfFile(input.path);
      } catch (const Error&) {
        digest.sha256.clear();  // unreadable now: recorded without its content
      }
    }
    run->inputs.push_back(std::move(digest));
  }
  return run;
}

json withProvenance(json document) {
  if (!document.is_object() || !document.contains("kind") || !document["kind"].is_string())
    return document;
  if (const std::optional<RunProvenance> run = currentRun())
    document["provenance"] = provenanceJson(*run, document["kind"].get<std::string>());
  return document;
}

std::vector<std::string> rerunDifferences(const json& original, const json& rerun,
                                          const std::vector<std::string>& output_options,
                                          std::size_t limit) {
  json a = withoutTimes(original), b = withoutTimes(rerun);
  // The rerun's command is the original's with its outputs elsewhere: those values are not
  // compared.
  if (a.contains("provenance") && b.contains("provenance") && a["provenance"].contains("command") &&
      b["provenance"].contains("command") && a["provenance"]["command"].is_array() &&
      b["provenance"]["command"].is_array()) {
    std::vector<std::string> ca, cb;
    for (const json& w : a["provenance"]["command"])
      ca.push_back(w.is_string() ? w.get<std::string>() : w.dump());
    for (const json& w : b["provenance"]["command"])
      cb.push_back(w.is_string() ? w.get<std::string>() : w.dump());
    for (const std::string& option : output_options) {
      const std::size_t ia = valueIndex(ca, option), ib = valueIndex(cb, option);
      if (ia != std::string::npos && ia == ib && ca.size() == cb.size()) {
        a["provenance"]["command"][ia] = nullptr;
        b["provenance"]["command"][ib] = nullptr;
      }
    }
  }
  std::vector<std::string> out;
  if (jsonText(a, 2) == jsonText(b, 2)) return out;
  differences(a, b, "", out);
  if (out.empty()) out.push_back("/: the same values, written differently");
  if (out.size() > limit) {
    const std::size_t rest = out.size() - limit;
    out.resize(limit);
    out.push_back("... and " + std::to_string(rest) + " more");
  }
  return out;
}

}  // namespace dynid
