// dynid: estimate and explain the inertial parameters of robot manipulators.
#include <csignal>
#include <exception>
#include <iostream>
#include <map>
#include <new>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/io.hpp"
#include "reports/output.hpp"

namespace {

const char* kUsage =
    "usage: dynid <command> [options]   (dynid <command> --help for its options)\n"
    "\n"
    "commands:\n"
    "  model show|check|export  inspect a robot, check physical consistency, export "
    "URDF/JSON/MJCF\n"
    "  dynamics                 inverse dynamics, mass matrix and forward dynamics at a state\n"
    "  simulate                 simulate a controlled robot and write a dataset CSV\n"
    "  prepare                  a raw log (irregular stamps, no ddq) into a filtered dataset CSV\n"
    "  identifiability          base parameters: what the torques can and cannot determine\n"
    "  excite                   design the motion that best determines the base parameters\n"
    "  identify                 least-squares (OLS/WLS/physically consistent) base parameters\n"
    "  predict                  a saved estimate's torques on a dataset, errors and a figure\n"
    "  payload                  what was added at the flange of an identified arm; drive gains\n"
    "  monitor                  watch a log or live samples for external torques (collisions)\n"
    "  audit                    do estimates from separate sessions agree within their sigma?\n"
    "  search                   the paper's GC-error search: nlo, ga or hybrid\n"
    "  refine                   Ceres least squares on the GC residuals from a search or estimate\n"
    "  demo                     the paper's study on the built-in PUMA 560, with a report\n"
    "  study                    every method on your own log: torque fit and motion prediction\n"
    "  batch                    a grid of study runs in parallel, resumable and shardable; merge\n"
    "\n"
    "robots: --robot puma560, puma560-consistent or panda (built in), a .urdf file, or a dynid "
    ".json "
    "model\n"
    "exit codes: 0 success, 1 runtime or data error, 2 usage error\n";

/// SIGTERM, SIGHUP and (outside a search's own handler) SIGINT: remove the temporaries of the
/// files being written, then die of the signal as before (exit status 128 + signal). While a set
/// of outputs is being renamed into place the signal waits for it (raised again after).
extern "C" void onTerminate(int signal) {
  if (dynid::deferSignalWhilePublishing(signal)) return;
  dynid::removeLiveTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynid::cli;
  const std::vector<std::string> all(argv + 1, argv + argc);
  if (all.empty()) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  const std::string& command = all[0];
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return kExitOk;
  }
  if (command == "--version") {
    std::cout << "dynid " << DYNID_VERSION << "\n";
    return kExitOk;
  }
  const std::map<std::string, int (*)(const std::vector<std::string>&)> commands = {
      {"model", runModel},       {"dynamics", runDynamics},
      {"simulate", runSimulate}, {"identifiability", runIdentifiability},
      {"identify", runIdentify}, {"search", runSearch},
      {"refine", runRefine},     {"demo", runDemo},
      {"batch", runBatch},       {"prepare", runPrepare},
      {"predict", runPredict},   {"study", runStudy},
      {"excite", runExcite},     {"payload", runPayload},
      {"monitor", runMonitor},   {"audit", runAudit}};
  const auto it = commands.find(command);
  if (it == commands.end()) {
    std::cerr << "dynid: unknown command '" << command << "'\n\n" << kUsage;
    return kExitUsage;
  }
  for (int signal : {SIGTERM, SIGHUP, SIGINT}) std::signal(signal, onTerminate);
  // A command never overwrites its own inputs; its output sets are recorded under its name.
  const dynid::InputFileGuard inputs;
  dynid::OutputSet::setCommand(command == "model" && all.size() > 1 ? "model-" + all[1] : command);
  try {
    return it->second(std::vector<std::string>(all.begin() + 1, all.end()));
  } catch (const UsageError& e) {
    std::cerr << "dynid " << command << ": " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << "dynid " << command
              << ": error: out of memory (the input is too large for this machine's memory or "
                 "the process's limit; nothing was written)\n";
    return kExitError;
  } catch (const std::exception& e) {
    std::cerr << "dynid " << command << ": error: " << e.what() << "\n";
    return kExitError;
  }
}
