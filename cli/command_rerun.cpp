// dynid rerun: a document's recorded command (its provenance) run again into a new folder, from
// the recorded working directory, its inputs checked by content first (analysis/records/rerun.hpp);
// the new document is then compared with the recorded one, time fields apart.
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "analysis/records/document.hpp"
#include "analysis/records/rerun.hpp"
#include "cli/build_info.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/io.hpp"

extern char** environ;

namespace dynid::cli {

namespace {

/// Runs this executable with `arguments` in `dir`, standard streams shared; its exit status
/// (128 + the signal that ended it).
int runCommand(const std::vector<std::string>& arguments, const std::string& dir) {
  const std::string self = selfExecutable();
  std::vector<std::string> words = {self};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  pid_t pid = 0;
  const int started = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) throw Error("cannot start " + self + ": " + std::strerror(started));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      throw Error("lost the rerun's process: " + std::string(std::strerror(errno)));
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

/// The document's folder with "-rerun" appended ("rerun" for a document in the current folder).
std::string defaultRerunFolder(const std::string& document) {
  const std::filesystem::path folder =
      std::filesystem::path(document).parent_path().lexically_normal();
  const std::string name = folder.filename().string();
  if (folder.empty() || name.empty() || name == "." || name == "..") return "rerun";
  return (folder.parent_path() / (name + "-rerun")).string();
}

/// The command as one line a user can read (words with spaces or quotes quoted).
std::string commandLine(const std::vector<std::string>& arguments) {
  std::string out = "dynid";
  for (const std::string& a : arguments) {
    const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$`") == std::string::npos;
    std::string quoted = "'";
    for (char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += " " + (plain ? a : quoted + "'");
  }
  return out;
}

}  // namespace

int runRerun(const std::vector<std::string>& args) {
  po::options_description options("dynid rerun");
  options.add_options()("document", po::value<std::string>()->required(),
                        "a document dynid wrote (estimate.json, search.json, ...)")(
      "out", po::value<std::string>(),
      "the new output folder (not the document's): the command's outputs, compared with it "
      "(default: the document's folder with -rerun appended: est/estimate.json reruns into "
      "est-rerun)");
  po::positional_options_description positional;
  positional.add("document", 1);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid rerun DOCUMENT [--out DIR]", vm, &positional))
    return kExitOk;
  RerunRequest request;
  request.document = vm["document"].as<std::string>();
  request.out = vm.count("out") ? outputDirectoryOption(vm) : defaultRerunFolder(request.document);
  request.version = DYNID_VERSION;
  request.commit = kBuildCommit;
  // The options whose value is a path a command writes: the output folder, then a search's
  // checkpoint and identify's URDF write-back (moved into the new folder by name).
  request.output_options = {"--out", "--checkpoint", "--write-urdf"};
  std::error_code error;
  if (std::filesystem::weakly_canonical(std::filesystem::absolute(request.out), error) ==
      std::filesystem::weakly_canonical(std::filesystem::absolute(request.document).parent_path(),
                                        error))
    throw UsageError(
        "--out is the folder the document is in: name another (the rerun is "
        "compared with the document there)");
  const RerunPlan plan = planRerun(request);
  printWarnings(plan.notes, "note: ");
  std::cerr << "rerunning (in " << plan.working_directory << "): " << commandLine(plan.arguments)
            << "\n";
  int status = 0;
  {
    const InterruptGuard guard;  // Ctrl-C ends the command; this one waits for it and says so
    status = runCommand(plan.arguments, plan.working_directory);
  }
  if (status == kExitInterrupted) {
    std::cerr << "dynid rerun: interrupted (Ctrl-C): nothing compared\n";
    return kExitInterrupted;
  }
  if (status != kExitOk)
    throw InputError("the rerun failed (exit status " + std::to_string(status) +
                     "; its messages above): nothing compared");
  const std::string again = (std::filesystem::path(request.out) / plan.document_name).string();
  const std::vector<std::string> differences =
      rerunDifferences(plan.original, parseJson(readFile(again), again), request.output_options);
  const std::string fields = plan.original["provenance"]["time_fields"].empty()
                                 ? "its times (the provenance's started and seconds)"
                                 : "its times (the provenance's started and seconds, and the "
                                   "fields its time_fields name)";
  if (differences.empty()) {
    std::cout << again << " is the same as " << request.document << " apart from " << fields
              << "\n";
    return kExitOk;
  }
  std::cout << again << " differs from " << request.document << " (apart from " << fields << "):\n";
  for (const std::string& d : differences) std::cout << "  " << d << "\n";
  std::cout << "A search, refinement, design or combined estimate that stopped at its time budget "
               "evaluates as many candidates as the time allows, so a rerun may stop elsewhere; "
               "one stopped by an evaluation or iteration budget, or by convergence, reruns "
               "the same (its termination says which).\n";
  return kExitError;
}

}  // namespace dynid::cli
