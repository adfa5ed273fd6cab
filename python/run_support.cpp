#include "python/run_support.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <thread>

#include "core/errors.hpp"
#include "data/digest/sha256.hpp"
#include "python/build_info.hpp"

namespace dynid::python {

namespace {

/// The calling Python code's file and line, and that line's source (empty where there is none).
std::pair<std::string, std::string> callSite() {
  const py::object frame = py::module_::import("sys").attr("_getframe")(0);
  const std::string file = py::str(frame.attr("f_code").attr("co_filename"));
  const int line = frame.attr("f_lineno").cast<int>();
  const std::string source =
      py::str(py::module_::import("linecache").attr("getline")(file, line).attr("strip")());
  return {file + ":" + std::to_string(line), source};
}

}  // namespace

PythonRun::PythonRun(const std::string& function, std::vector<std::string> files,
                     std::optional<std::uint64_t> seed, std::optional<int> threads)
    : files_(std::move(files)), start_(std::chrono::steady_clock::now()) {
  run_.interface = "python";
  run_.version = DYNID_VERSION;
  run_.commit = kBuildCommit;
  const auto [where, source] = callSite();
  run_.command = {"dynid." + function, where, source};
  std::error_code error;
  run_.working_directory = std::filesystem::current_path(error).string();
  run_.seed = seed;
  if (threads)
    run_.threads = *threads > 0
                       ? *threads
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  run_.started = utcTimestamp(std::chrono::system_clock::now());
}

RunProvenance PythonRun::finish() const {
  RunProvenance run = run_;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  for (const std::string& file : files_) {
    // An argument not given as a file: none, or in memory ("<arrays>", "<search>", ...).
    if (file.empty() || file.front() == '<') continue;
    InputDigest digest{file, ""};
    struct stat st {};
    if (::stat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
      try {
        digest.sha256 = sha256OfFile(file);
      } catch (const Error&) {
        digest.sha256.clear();  // unreadable now: recorded without its content
      }
    }
    run.inputs.push_back(std::move(digest));
  }
  return run;
}

nlohmann::json withCall(nlohmann::json document, const RunProvenance& call) {
  if (!call.interface.empty() && document.is_object() && document.contains("kind") &&
      document["kind"].is_string())
    document["provenance"] = provenanceJson(call, document["kind"].get<std::string>());
  return document;
}

}  // namespace dynid::python
