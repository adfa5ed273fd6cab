#include "cli/batch_workers.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cli/common.hpp"
#include "core/errors.hpp"

extern char** environ;

namespace dynid::cli {

BatchOutcome runBatchWorkers(const BatchPlan& plan, int jobs, const std::atomic<bool>* stop,
                             const std::function<void(const FinishedRun&)>& on_finished) {
  const auto stopped = [&] { return stop != nullptr && stop->load(); };
  std::filesystem::create_directories(plan.dir + "/runs");
  const std::string worker = selfExecutable();
  std::vector<std::string> failed;
  // Worker processes, `jobs` at a time.
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0, finished = 0;
  bool terminated = false;
  while ((next < plan.todo.size() && !stopped()) || !running.empty()) {
    while (next < plan.todo.size() && static_cast<int>(running.size()) < jobs && !stopped()) {
      const std::size_t i = plan.todo[next++];
      // --parent: the worker ends when this process does (batch run, PR_SET_PDEATHSIG).
      const std::vector<std::string> argv_strings = {worker,
                                                     "batch",
                                                     "run",
                                                     "--spec",
                                                     plan.runs[i].dump(),
                                                     "--out",
                                                     plan.path(i),
                                                     "--parent",
                                                     std::to_string(::getpid())};
      std::vector<char*> argv;
      for (const std::string& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      pid_t pid = 0;
      if (posix_spawn(&pid, worker.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
        failed.push_back(batchRunName(i, plan.runs[i]) + " (could not start a worker)");
        continue;
      }
      running[pid] = i;
    }
    if (running.empty()) break;
    // Ctrl-C: the running workers are ended (SIGTERM: they remove their temporaries; their runs
    // count as missing and run again on resume), so that the batch stops within a second
    // instead of after its longest run. Polled: SIGINT does not interrupt a blocking waitpid.
    if (stopped() && !terminated) {
      for (const auto& [worker_pid, index] : running) ::kill(worker_pid, SIGTERM);
      terminated = true;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid == 0) {
      ::usleep(20000);
      continue;
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t i = it->second;
    running.erase(it);
    ++finished;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!ok && !stopped()) failed.push_back(batchRunName(i, plan.runs[i]));
    if (on_finished) on_finished({finished, plan.todo.size(), i, ok});
  }
  BatchOutcome out = collectBatch(plan);
  out.failed = std::move(failed);
  out.interrupted = stopped();
  return out;
}

}  // namespace dynid::cli
