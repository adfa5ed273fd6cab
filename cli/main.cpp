// dynid: estimate and explain the inertial parameters of robot manipulators.
#include <csignal>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli/command_table.hpp"
#include "cli/spelling.hpp"
#include "data/io.hpp"
#include "reports/output.hpp"
#include "search/refinement/refine.hpp"

namespace {

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
    std::cerr << usageText();
    return kExitUsage;
  }
  std::string command = all[0];
  std::vector<std::string> args(all.begin() + 1, all.end());
  if (command == "--help" || command == "-h" || (command == "help" && args.empty())) {
    std::cout << usageText();
    return kExitOk;
  }
  if (command == "--version") {
    std::cout << "dynid " << versionText() << "\n";
    return kExitOk;
  }
  if (command == "help") {  // dynid help identify, dynid help model export
    command = args[0];
    args.erase(args.begin());
    args.emplace_back("--help");
  }
  const CommandEntry* entry = findCommand(command);
  if (entry == nullptr) {
    std::cerr << "dynid: unknown command '" << command << "'\n\n" << usageText();
    return kExitUsage;
  }
  for (int signal : {SIGTERM, SIGHUP, SIGINT}) std::signal(signal, onTerminate);
  dynid::silenceSolverLog();  // Ceres' log lines: dynid reports every termination itself
  // A command never overwrites its own inputs; its output sets are recorded under its name.
  const dynid::InputFileGuard inputs;
  dynid::OutputSet::setCommand(command == "model" && !args.empty() ? "model-" + args[0] : command);
  beginCommandRun(all);  // what its documents' provenance records
  try {
    return entry->run(args);
  } catch (const UsageError& e) {
    std::cerr << "dynid " << command << ": " << cliText(e.what()) << "\n";
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << "dynid " << command
              << ": error: out of memory (the input is too large for this machine's memory or "
                 "the process's limit; nothing was written)\n";
    return kExitError;
  } catch (const std::exception& e) {
    std::cerr << "dynid " << command << ": error: " << cliText(e.what()) << "\n";
    return kExitError;
  }
}
